/* order-pair N|MESH [ROUNDS]: energy+gradient time per vertex of one tissue in
 * its own numbering and renumbered by mesh_order_spatial (MESH_ORDER_ALL),
 * the two alternating in one process (thread CPU time, best and mean of
 * ROUNDS, default 10), with both energies (bench/RESULTS.md, "Spatial
 * order", order4).  N: a perturbed N-cell honeycomb as energy-bench makes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include "geom.h"
#include "lattice.h"
#include "order.h"
static double now(void){struct timespec t;clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t);return t.tv_sec+1e-9*t.tv_nsec;}
int main(int argc,char**argv){
  mesh *m; mesh_error err; const char *a=argv[1]; int rounds=argc>2?atoi(argv[2]):10;
  if(strchr(a,'/')){FILE*f=fopen(a,"r");long line=0;if(!f||mesh_read(f,&line,&m,&err))return 1;fclose(f);}
  else{int nx=(int)lround(sqrt(atof(a)));nx+=nx%2;if(lattice_honeycomb(nx,nx,&m,&err))return 1;
    for(int i=0;i<2*m->nv;i++) m->r[i]+=0.05*sin(12.9898*i);}
  mesh *o=mesh_copy(m); if(mesh_order_spatial(o,MESH_ORDER_ALL))return 1;
  mesh *ms[2]={m,o}; energy_ws *w[2]={energy_ws_alloc(m),energy_ws_alloc(o)};
  double *g=malloc(16*(size_t)m->nv); model p={3.7,100}; double e[2],best[2]={INFINITY,INFINITY},sum[2]={0,0};
  long reps=(long)(2e6/m->nv)+1;
  for(int r=0;r<rounds;r++) for(int s=0;s<2;s++){int k=(r&1)?1-s:s;
    double t0=now(); for(long q=0;q<reps;q++) e[k]=mesh_energy(ms[k],ms[k]->r,&p,g,w[k]); double dt=(now()-t0)/reps/m->nv*1e9;
    if(dt<best[k])best[k]=dt; sum[k]+=dt;}
  printf("%d cells %d verts: own order best %.2f mean %.2f ns/v  hilbert best %.2f mean %.2f  ratio(best) %.3f  E %.17g %.17g\n",
    m->nc,m->nv,best[0],sum[0]/rounds,best[1],sum[1]/rounds,best[1]/best[0],e[0],e[1]);
  return 0;}
