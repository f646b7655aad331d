/* energy.c - the vertex-model energy W and its gradient (the kernel every
 * minimizer and integrator calls), on threads and in an AVX2 build, and
 * the explicit Euler move that shares the kernel's threads and build. */
#include "energy.h"
#include "vec2.h"

#include <math.h>
#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#ifdef __SSE3__
#include <pmmintrin.h>
#endif
/* The kernel is also built for AVX2 and picked at run time
 * (energy_ws_simd), where the default target lacks it. */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(__AVX2__)
#define ENERGY_HAVE_AVX2 1
#include <immintrin.h>   /* declares the AVX builtins (pass_lengths4) */
#endif

model model_from_mesh(const mesh *m)
{
	model p = { .p0 = 3.6, .ka = 100.0 };
	mesh_param_get(m, "p0", &p.p0);
	mesh_param_get(m, "ka", &p.ka);
	return p;
}

/* Vertices above which the tissue's arrays (~150 bytes per vertex) no
 * longer stay in the cache, and the kernel trades instructions for bytes
 * (bench/RESULTS.md, "The kernel, per vertex"): below, the packed codes
 * and the fused pass cost 1-4 % more time than they save. */
#ifndef KERNEL_BIG_NV
#define KERNEL_BIG_NV 65536
#endif

/* W is summed per block of this many cells, the blocks' sums then in
 * block order: the same blocks for any thread count, so the same W; a
 * tissue of at most this many cells sums as one block, its W the plain
 * sum in cell order. */
#define KERNEL_WBLOCK 1024

struct energy_ws {
	int nv, nc, nj;
	int simd;     /* 1: the kernel's AVX2 build (energy_ws_simd) */
	int nthr;     /* threads (energy_ws_threads); 1: none */
	int par_nv;   /* the fewest vertices that use them */
	int *fj;      /* threads: per vertex its lowest-numbered junction */
	double *wblk; /* threads: per block of cells the sum of their W */
	int dcap;     /* per thread: room for this many deferred terms */
	int *dn;      /* per thread: deferred terms held */
	int *dv;      /* per thread, dcap: 2 v + (the vertex's last junction) */
	double *dt;   /* per thread, 2 dcap: the terms */
	double *q2;   /* per thread: its largest |grad_v|^2 */
	int ovf;      /* a thread ran out of room: pass 3 again, serially */
	double *len;  /* per junction: its length */
	double *vec;  /* 2 per junction: its vector; NULL on a large tissue,
	                 where the gradient pass computes it again */
	double *cc;   /* in cache (forms 0, 3): per cell the pair (dW/dA,
	                 dW/dP), which the gradient pass reads with one load
	                 each from its cells' byte offsets kjc (loads, not
	                 instructions, set that pass's time); forms 1, 2: per
	                 cell dW/dA, then per cell dW/dP, apart, so that the
	                 pass indexes them by cell id without a shift */
};

energy_ws *energy_ws_alloc(const mesh *m)
{
	energy_ws *w = malloc(sizeof *w);
	if (w == NULL)
		return NULL;
	w->nv = m->nv;
	w->nc = m->nc;
	w->nj = m->nj;
	w->simd = 0;
	w->nthr = 1;
	w->par_nv = ENERGY_PAR_NV;
	w->fj = w->dn = w->dv = NULL;
	w->wblk = w->dt = w->q2 = NULL;
	energy_ws_simd(w, 1);
	w->len = malloc(((size_t)m->nj + 1) * sizeof *w->len);
	w->vec = m->nv <= KERNEL_BIG_NV ? malloc((2 * (size_t)m->nj + 1) * sizeof *w->vec) : NULL;
	w->cc = malloc((2 * (size_t)m->nc + 1) * sizeof *w->cc);
	if (w->len == NULL || w->cc == NULL || (m->nv <= KERNEL_BIG_NV && w->vec == NULL)) {
		energy_ws_free(w);
		return NULL;
	}
	return w;
}

/* The threads' scratch freed: w serial. */
static void ws_serial(energy_ws *w)
{
	free(w->fj);
	free(w->wblk);
	free(w->dn);
	free(w->dv);
	free(w->dt);
	free(w->q2);
	w->fj = w->dn = w->dv = NULL;
	w->wblk = w->dt = w->q2 = NULL;
	w->nthr = 1;
}

void energy_ws_free(energy_ws *w)
{
	if (w == NULL)
		return;
	ws_serial(w);
	free(w->len);
	free(w->vec);
	free(w->cc);
	free(w);
}

int energy_ws_threads(energy_ws *w, int n, int min_nv)
{
	if (n < 1 || n > ENERGY_MAXTHREADS)
		return MESH_EDOM;
	w->par_nv = min_nv > 0 ? min_nv : ENERGY_PAR_NV;
	ws_serial(w);
#ifndef _OPENMP
	n = 1;
#endif
	if (n == 1)
		return MESH_OK;
	/* the terms deferred at the seams between the threads' junction
	 * ranges: in spatial order about two rows of cells per seam (680
	 * ends per seam at 10^5 cells, measured: bench/RESULTS.md, "Every
	 * core"); more than this room, and pass 3 runs again serially, the
	 * same numbers */
	size_t cap = (size_t)w->nj / (8 * (size_t)n) + 4096;
	w->dcap = (int)(cap < (size_t)1 << 30 ? cap : (size_t)1 << 30);
	w->fj = malloc(((size_t)w->nv + 1) * sizeof *w->fj);
	w->wblk = malloc(((size_t)w->nc / KERNEL_WBLOCK + 2) * sizeof *w->wblk);
	w->dn = malloc((size_t)n * sizeof *w->dn);
	w->q2 = malloc((size_t)n * sizeof *w->q2);
	w->dv = malloc((size_t)n * w->dcap * sizeof *w->dv);
	w->dt = malloc(2 * (size_t)n * w->dcap * sizeof *w->dt);
	if (!w->fj || !w->wblk || !w->dn || !w->q2 || !w->dv || !w->dt) {
		ws_serial(w);
		return MESH_ENOMEM;
	}
	w->nthr = n;
	return MESH_OK;
}

int energy_ws_nthreads(const energy_ws *w, int nv)
{
	return nv >= w->par_nv ? w->nthr : 1;
}

double mesh_energy(const mesh *m, const double *r, const model *p,
                   double *grad, energy_ws *w)
{
	return mesh_energy_tension(m, r, p, NULL, grad, w);
}

void mesh_junction_vectors(const mesh *m, const double *r, double *jd)
{
	const int nj = m->nj;
	const int *restrict jv = m->jv;
	const v2d *r2 = (const v2d *)r;
	const v2d *restrict jimg = (const v2d *)m->jimg;
	for (int j = 0; j < nj; j++) {
		v2d d = r2[jv[2 * j + 1]] - r2[jv[2 * j]] + jimg[j];
		v2d q = d * d;
		*(v2d *)(jd + 3 * j) = d;
		jd[3 * j + 2] = sqrt(q[0] + q[1]);
	}
}

/* The area is the shoelace sum relative to the first corner; its cross
 * products are accumulated as pairs (sum of x_i y_j and of y_i x_j apart)
 * and subtracted once per cell.  From them and the perimeter: dW/dA and
 * dW/dP into *fa, *fp, and the cell's energy. */
static inline double cell_factor(v2d acc, double per, double ka, double p0, double *fa, double *fp)
{
#ifdef __SSE3__
	/* acc[0] - acc[1] in one instruction (GCC otherwise copies and
	 * shuffles: 2) */
	double a = 0.5 * _mm_cvtsd_f64(_mm_hsub_pd((__m128d)acc, (__m128d)acc));
#else
	double a = 0.5 * (acc[0] - acc[1]);
#endif
	double da = a - 1, dp = per - p0;
	*fa = 2 * ka * da;
	*fp = 2 * dp;
	return ka * da * da + dp * dp;
}

double mesh_cell_factors(const mesh *m, const double *r, const model *p,
                         const double *jd, double *cc)
{
	const int nc = m->nc;
	const int *restrict coff = m->coff, *restrict cv = m->cv, *restrict cj = m->cj;
	const v2d *r2 = (const v2d *)r;
	const v2d *restrict cimg = (const v2d *)m->cimg;
	const double ka = p->ka, p0 = p->p0;
	double W = 0;
	for (int k = 0; k < nc; k++) {
		int s = coff[k], e = coff[k + 1];
		v2d x0 = r2[cv[s]], acc = { 0, 0 }, prev = { 0, 0 };
		double per = jd[3 * cj[s] + 2];
		for (int i = s + 1; i < e; i++) {
			v2d q = r2[cv[i]] + cimg[i] - x0;
			acc += prev * v2d_swap(q);
			per += jd[3 * cj[i] + 2];
			prev = q;
		}
		W += cell_factor(acc, per, ka, p0, cc + 2 * k, cc + 2 * k + 1);
	}
	return W;
}

const double *energy_ws_lengths(const energy_ws *w)
{
	return w->len;
}

/* (y, x) from (x, y) in one instruction: v2d_swap compiles to a copy and
 * a palignr, pshufd needs no copy (3 instructions less per vertex). */
static inline v2d swap1(v2d a)
{
#ifdef __SSE2__
	return (v2d)_mm_shuffle_epi32((__m128i)a, 0x4e);
#else
	return v2d_swap(a);
#endif
}

/* The largest |g_v|^2, NaNs passed over (as the dynamics always did): two
 * vertices at a time, each lane a maximum of its own (exact, so the two
 * combine to the same number in any order). */
static inline __attribute__((always_inline)) double gmax2(int nv, const v2d *g)
{
	v2d f2 = { 0, 0 };
	int v = 0;
	for (; v + 1 < nv; v += 2) {
		v2d q = v2d_hadd(g[v] * g[v], g[v + 1] * g[v + 1]);
#ifdef __SSE2__
		f2 = (v2d)_mm_max_pd((__m128d)q, (__m128d)f2);   /* q > f2 ? q : f2 */
#else
		f2 = (v2d){ q[0] > f2[0] ? q[0] : f2[0], q[1] > f2[1] ? q[1] : f2[1] };
#endif
	}
	double m = f2[1] > f2[0] ? f2[1] : f2[0];
	if (v < nv) {
		v2d q = g[v] * g[v];
		m = q[0] + q[1] > m ? q[0] + q[1] : m;
	}
	return m;
}

/* gmax2 for the AVX2 build, four vertices at a time: the same sum
 * x^2 + y^2 per vertex (unpacklo/hi pair each vertex's squares), and a
 * compare and select that keeps the old maximum where the new value is
 * not greater (NaN included), as maxpd does.  Lowered to SSE it would
 * cost more than gmax2, so the portable build keeps that. */
typedef double v4d __attribute__((vector_size(32), aligned(8)));
typedef long long v4i __attribute__((vector_size(32)));

static inline __attribute__((always_inline)) double gmax4(int nv, const v2d *g)
{
	/* a pointer, not g4[v / 2]: the halving and its sign extension cost
	 * 4 instructions per iteration */
	const v4d *g4 = (const v4d *)g, *g4e = g4 + 2 * (nv / 4);
	v4d f2 = { 0, 0, 0, 0 };
	int v = 4 * (nv / 4);
	for (; g4 < g4e; g4 += 2) {
		v4d p = g4[0] * g4[0], q = g4[1] * g4[1];
#ifdef __clang__
		v4d s = __builtin_shufflevector(p, q, 0, 4, 2, 6) + __builtin_shufflevector(p, q, 1, 5, 3, 7);
#else
		v4d s = __builtin_shuffle(p, q, (v4i){ 0, 4, 2, 6 }) + __builtin_shuffle(p, q, (v4i){ 1, 5, 3, 7 });
#endif
		v4i gt = s > f2;
		f2 = (v4d)(((v4i)s & gt) | ((v4i)f2 & ~gt));
	}
	double m = 0;
	for (int k = 0; k < 4; k++)
		m = f2[k] > m ? f2[k] : m;
	for (; v < nv; v++) {
		v2d q = g[v] * g[v];
		m = q[0] + q[1] > m ? q[0] + q[1] : m;
	}
	return m;
}

/* The pair at byte offset off of base. */
static inline v2d at(const v2d *base, size_t off)
{
	return *(const v2d *)((const char *)base + off);
}

/* Junction j's vector, from the packed codes (form 2) or from the mesh's
 * own arrays, its vertices addressed by the byte offsets kjo (form 0)
 * or by jv: the same numbers either way. */
static inline __attribute__((always_inline)) v2d
jvec(const mesh *m, const v2d *r2, int j, int form)
{
	if (form == 2) {
		unsigned u = m->kjv[2 * j];
		return r2[m->kjv[2 * j + 1] & MESH_KMASK] - r2[u & MESH_KMASK] +
		       ((const v2d *)m->kimg)[u >> MESH_KSHIFT];
	}
	if (form == 0)
		return at(r2, m->kjo[2 * j + 1]) - at(r2, m->kjo[2 * j]) + ((const v2d *)m->jimg)[j];
	return r2[m->jv[2 * j + 1]] - r2[m->jv[2 * j]] + ((const v2d *)m->jimg)[j];
}

/* Corner i of a cell, relative to its first corner x0. */
static inline __attribute__((always_inline)) v2d
corner(const mesh *m, const v2d *r2, int i, v2d x0, int packed)
{
	if (packed) {
		unsigned u = m->kcv[i];
		return r2[u & MESH_KMASK] + ((const v2d *)m->kimg)[u >> MESH_KSHIFT] - x0;
	}
	return r2[m->cv[i]] + ((const v2d *)m->cimg)[i] - x0;
}

/* Three passes keep every loop simple enough to pipeline: junction
 * lengths (one sqrt per junction, not per cell side), cell areas and
 * perimeters, then the gradient assembled per junction.  A junction a->b
 * with vector d, unit u, ccw in cell L and cw in cell R gets
 *   dW/dr_b = +(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 *   dW/dr_a = -(Pw_L + Pw_R) u + (Aw_L - Aw_R) perp(d)/2,
 * with Pw = 2 (P - p0), Aw = 2 ka (A - 1) and perp(d) = (dy, -dx), because
 * each polygon side adds perp(d)/2 to dA/dr of both its end points.  A
 * junction tension dg adds to the line tension Pw_L + Pw_R: same pass.
 * On a tissue larger than the caches the passes stream their arrays from
 * memory, so the bytes per vertex set the time: only lengths are kept
 * between passes (the third pass computes the vectors again, from
 * coordinates that the spatial order keeps in cache), and with packed
 * codes (mesh_kernel_build) a corner is 4 bytes and a junction 8. */
/* Pass 1, junctions j0 <= j < j1: lengths, and in cache the vectors. */
static inline __attribute__((always_inline)) void
pass_lengths(const mesh *m, const v2d *r2, energy_ws *w, int j0, int j1, const int form)
{
	double *restrict len = w->len;
	v2d *restrict vec = (v2d *)w->vec;
	int j = j0;
	for (; j + 1 < j1; j += 2) {
		v2d d0 = jvec(m, r2, j, form), d1 = jvec(m, r2, j + 1, form);
		if (form == 0 || form == 3) {
			vec[j] = d0;
			vec[j + 1] = d1;
		}
		*(v2d *)(len + j) = v2d_sqrt(v2d_hadd(d0 * d0, d1 * d1));
	}
	if (j < j1) {
		v2d d = jvec(m, r2, j, form);
		if (form == 0 || form == 3)
			vec[j] = d;
		len[j] = v2d_sqrt(v2d_hadd(d * d, d * d))[0];
	}
}

#ifdef ENERGY_HAVE_AVX2
/* Pass 1 in cache for the AVX2 build: four junctions' square roots as one
 * vsqrtpd, which costs what one of two lanes does (bench/RESULTS.md):
 * the divider, not the instructions, sets pass 1's time.  The same
 * correctly rounded operation per lane, so the same lengths.  A builtin,
 * not _mm256_sqrt_pd: the portable build inlines this too (as dead
 * code), which a target("avx") intrinsic forbids; the ABI note on a
 * 256-bit vector return (-Wpsabi) concerns calls, of which there are
 * none. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
static inline __attribute__((always_inline)) void
pass_lengths4(const mesh *m, const v2d *r2, energy_ws *w, int j0, int j1, const int form)
{
	double *restrict len = w->len;
	v2d *restrict vec = (v2d *)w->vec;
	int j = j0;
	for (; j + 3 < j1; j += 4) {
		v2d d0 = jvec(m, r2, j, form), d1 = jvec(m, r2, j + 1, form);
		v2d d2 = jvec(m, r2, j + 2, form), d3 = jvec(m, r2, j + 3, form);
		vec[j] = d0;
		vec[j + 1] = d1;
		vec[j + 2] = d2;
		vec[j + 3] = d3;
		v2d q01 = v2d_hadd(d0 * d0, d1 * d1), q23 = v2d_hadd(d2 * d2, d3 * d3);
#ifdef __clang__
		/* clang refuses the builtin where the portable build inlines it */
		*(v2d *)(len + j) = v2d_sqrt(q01);
		*(v2d *)(len + j + 2) = v2d_sqrt(q23);
#else
		*(v4d *)(len + j) = __builtin_ia32_sqrtpd256((v4d){ q01[0], q01[1], q23[0], q23[1] });
#endif
	}
	pass_lengths(m, r2, w, j, j1, form);
}
#pragma GCC diagnostic pop
#endif

/* Pass 2, cells k0 <= k < k1: dW/dA and dW/dP into cc, their energies
 * added to W in cell order.  Two corners per iteration: no copy of the
 * previous corner, half the loop tests. */
static inline __attribute__((always_inline)) double
pass_cells(const mesh *m, const v2d *r2, const model *p, energy_ws *w, int k0, int k1,
           double W, const int form)
{
	const int packed = form == 2;
	const int *restrict coff = m->coff, *restrict cj = m->cj;
	const double *restrict len = w->len;
	double *restrict aw = w->cc, *restrict pw = w->cc + m->nc;
	const double ka = p->ka, p0 = p->p0;
	for (int k = k0; k < k1; k++) {
		int s = coff[k], e = coff[k + 1], i = s + 1;
		v2d x0 = r2[packed ? (int)(m->kcv[s] & MESH_KMASK) : m->cv[s]], acc = { 0, 0 }, prev = { 0, 0 };
		double per = len[cj[s]];
		for (; i + 1 < e; i += 2) {
			v2d q = corner(m, r2, i, x0, packed);
			acc += prev * swap1(q);
			per += len[cj[i]];
			prev = corner(m, r2, i + 1, x0, packed);
			acc += q * swap1(prev);
			per += len[cj[i + 1]];
		}
		if (i < e) {
			v2d q = corner(m, r2, i, x0, packed);
			acc += prev * swap1(q);
			per += len[cj[i]];
		}
		W += cell_factor(acc, per, ka, p0, aw + k, pw + k);
	}
	return W;
}

/* Pass 2 of a tissue in cache (forms 0 and 3): pass_cells' operations
 * in its order, with one induction variable o, the corner's byte offset
 * in kco and cj (4 o in cimg), the vertex's byte offset from kco (form
 * 0: no shift per corner) and the arrays in locals (GCC reloaded
 * m->cimg from the stack for every cell).  Tried and not kept: starting
 * a cell of even size at its first corner (exactly (+0, +0)), which
 * drops the remainder and the trip-count arithmetic, 4 % fewer
 * instructions per step, but makes the cell's two sums one addition
 * longer, and was 1-4 % slower (bench/RESULTS.md): the chains of
 * additions, not the instructions, set this pass's time. */
static inline __attribute__((always_inline)) double
pass_cells_cache(const mesh *m, const v2d *r2, const model *p, energy_ws *w, int k0, int k1,
                 double W, const int form)
{
	const int *restrict coff = m->coff;
	const char *restrict cjb = (const char *)m->cj;
	const char *restrict cob = form == 0 ? (const char *)m->kco : (const char *)m->cv;
	const char *restrict cimgb = (const char *)m->cimg;
	const double *restrict len = w->len;
	double *restrict cc = w->cc;
	const double ka = p->ka, p0 = p->p0;
	size_t os = 4 * (size_t)coff[k0];
#define CORNER_OFF(o) (form == 0 ? (size_t)*(const unsigned *)(cob + (o)) : \
                       16 * (size_t)*(const int *)(cob + (o)))
#define CORNER_LEN(o) len[*(const int *)(cjb + (o))]
#define CORNER(o) (at(r2, CORNER_OFF(o)) + *(const v2d *)(cimgb + 4 * (o)) - x0)
	for (int k = k0; k < k1; k++) {
		size_t oe = 4 * (size_t)coff[k + 1], o = os + 4;
		v2d x0 = at(r2, CORNER_OFF(os)), acc = { 0, 0 }, prev = { 0, 0 };
		double per = CORNER_LEN(os);
		for (; o + 4 < oe; o += 8) {
			v2d q = CORNER(o);
			acc += prev * swap1(q);
			per += CORNER_LEN(o);
			prev = CORNER(o + 4);
			acc += q * swap1(prev);
			per += CORNER_LEN(o + 4);
		}
		if (o < oe) {
			v2d q = CORNER(o);
			acc += prev * swap1(q);
			per += CORNER_LEN(o);
		}
		W += cell_factor(acc, per, ka, p0, cc + 2 * k, cc + 2 * k + 1);
		os = oe;
	}
#undef CORNER
#undef CORNER_LEN
#undef CORNER_OFF
	return W;
}

/* Where a thread's pass 3 puts a term it may not add in place (threads
 * only; energy_par): the terms of a vertex whose sum began in an earlier
 * thread's junctions, kept in junction order and added after the others
 * by one thread, in the order of the threads' ranges, so that every sum
 * is the serial one, bit for bit. */
typedef struct {
	const int *fj;  /* per vertex its first junction */
	int j0;         /* the thread's first junction */
	int n, cap;
	int *dv;        /* 2 v + (the vertex's last junction) */
	v2d *dt;
} defer;

static inline __attribute__((always_inline)) void
defer_push(defer *d, int v, int last, v2d t)
{
	if (d->n < d->cap) {
		d->dv[d->n] = 2 * v + last;
		d->dt[d->n] = t;
	}
	d->n++;
}

/* Pass 3 of a tissue in memory, junctions j0 <= j < j1, with the codes: a
 * vertex's sum starts at its first junction (0 + term, the same number
 * as adding to a zeroed array) and is complete at its last, where its
 * square enters the maximum *q2 (if g2max): no pass to zero the gradient
 * and none to find the largest force, 48 bytes per vertex less from
 * memory, for about 10 instructions more per junction, which in cache
 * cost more than they save.  Masks instead of branches, as first and last
 * follow no pattern the branch predictor learns.  par: d holds the
 * thread's deferred terms. */
static inline __attribute__((always_inline)) void
pass_grad_codes(const mesh *m, const v2d *r2, const double *dg, energy_ws *w, v2d *g2,
                int j0, int j1, double *g2max, double *q2p, const int tens, defer *d,
                const int par)
{
	const int *restrict jc = m->jc;
	const unsigned *restrict kjv = m->kjv;
	const double *restrict len = w->len;
	const double *restrict aw = w->cc, *restrict pw = w->cc + m->nc;
	double q2 = *q2p;
	for (int j = j0; j < j1; j++) {
		int L = jc[2 * j], R = jc[2 * j + 1];
		int a = (int)(kjv[2 * j] & MESH_KMASK), b = (int)(kjv[2 * j + 1] & MESH_KMASK);
		v2d dv = jvec(m, r2, j, 2);
		long long fl = kjv[2 * j + 1] >> MESH_KSHIFT;
		double t = (pw[L] + pw[R] + (tens ? dg[j] : 0.0)) / len[j];
		double x = aw[L] - aw[R];
		v2d perp = (v2d){ x, x } * (v2d){ 0.5, -0.5 } * swap1(dv), tan = t * dv;
		if (par && d->fj[a] < d->j0) {
			defer_push(d, a, (fl & MESH_KLAST_A) != 0, perp - tan);
		} else {
			v2i keep_a = (v2i){ 0, 0 } - ((fl & MESH_KFIRST_A) == 0);
			v2d ga = (v2d)((v2i)g2[a] & keep_a) + (perp - tan);
			g2[a] = ga;
			if (g2max) {
				v2d qa = ga * ga;
				double sa = fl & MESH_KLAST_A ? qa[0] + qa[1] : 0.0;
				q2 = sa > q2 ? sa : q2;
			}
		}
		if (par && d->fj[b] < d->j0) {
			defer_push(d, b, (fl & MESH_KLAST_B) != 0, perp + tan);
		} else {
			v2i keep_b = (v2i){ 0, 0 } - ((fl & MESH_KFIRST_B) == 0);
			v2d gb = (v2d)((v2i)g2[b] & keep_b) + (perp + tan);
			g2[b] = gb;
			if (g2max) {
				v2d qb = gb * gb;
				double sb = fl & MESH_KLAST_B ? qb[0] + qb[1] : 0.0;
				q2 = sb > q2 ? sb : q2;
			}
		}
	}
	*q2p = q2;
}

/* Pass 3 of forms 0, 1 and 3 (below), junctions j0 <= j < j1, into a
 * gradient the caller zeroed.  par (form 0 only): d holds the thread's
 * deferred terms. */
static inline __attribute__((always_inline)) void
pass_grad(const mesh *m, const v2d *r2, const double *dg, energy_ws *w, v2d *g2,
          int j0, int j1, const int form, const int tens, defer *d, const int par)
{
	const double *restrict aw = w->cc, *restrict pw = w->cc + m->nc;
	const v2d *restrict cc2 = (const v2d *)w->cc;  /* forms 0, 3 */
	/* One induction variable, o = 8 j, the byte offset of junction j's
	 * pair in jc, kjc, kjo and jv and of its length (2 o that of its vector):
	 * x86 scales an index by 8 at most, so j itself would need a shift
	 * and a copy per junction for vec.  Without tensions the line
	 * tension is pw[L] + pw[R] alone: adding 0.0 would only turn a -0
	 * into +0, which changes no sum of the gradient (each starts at +0
	 * and so never becomes -0), and costs an instruction. */
	const char *restrict jcb = (const char *)m->jc, *restrict lenb = (const char *)w->len;
	const char *restrict vecb = (const char *)w->vec;
	const char *restrict job = form == 0 ? (const char *)m->kjo : (const char *)m->jv;
	const char *restrict jcob = (const char *)m->kjc;
	const char *restrict dgb = (const char *)dg;
	/* The sums read through gl and written through gs, the same address:
	 * GCC, not seeing that, addresses each access as base + offset
	 * instead of adding the two into a register first (2 instructions
	 * less per junction). */
	char *gs = (char *)g2, *gl = gs;
#ifdef __GNUC__
	__asm__("" : "+r"(gl));
#endif
	const size_t oend = 8 * (size_t)j1;
	for (size_t o = 8 * (size_t)j0; o < oend; o += 8) {
		int L = 0, R = 0;
		size_t oL, oR;
		if (form == 0) {
			oL = *(const unsigned *)(jcob + o);
			oR = *(const unsigned *)(jcob + o + 4);
		} else {
			L = *(const int *)(jcb + o);
			R = *(const int *)(jcb + o + 4);
			oL = 16 * (size_t)L;
			oR = 16 * (size_t)R;
		}
		size_t oa, ob;
		if (form == 0) {
			oa = *(const unsigned *)(job + o);
			ob = *(const unsigned *)(job + o + 4);
		} else {
			oa = 16 * (size_t)*(const int *)(job + o);
			ob = 16 * (size_t)*(const int *)(job + o + 4);
		}
		v2d dv = form == 1 ? jvec(m, r2, (int)(o / 8), 1) : *(const v2d *)(vecb + 2 * o);
#ifdef __GNUC__
		/* in a register: GCC would read it twice from memory, and the
		 * loads, not the instructions, are what this loop waits on */
		__asm__("" : "+x"(dv));
#endif
		double s, l = *(const double *)(lenb + o);
		v2d xx, tt;
		if (form == 1) {
			s = pw[L] + pw[R];
			if (tens)
				s += *(const double *)(dgb + o);
			double x = aw[L] - aw[R];
			xx = (v2d){ x, x };
			tt = (v2d){ s / l, s / l };
		} else {
			/* (aw_L - aw_R, pw_L + pw_R) from two loads: a + (-b) is
			 * a - b, bit for bit; the quotient broadcast as a divpd
			 * of the broadcast operands, the same number */
			v2d c = at(cc2, oL) + at(cc2, oR) * (v2d){ -1, 1 };
			s = c[1];
			if (tens)
				s += *(const double *)(dgb + o);
			xx = (v2d){ c[0], c[0] };
			tt = (v2d){ s, s } / (v2d){ l, l };
		}
		v2d perp = xx * (v2d){ 0.5, -0.5 } * swap1(dv), tan = tt * dv;
		if (par && d->fj[oa / 16] < d->j0)
			defer_push(d, (int)(oa / 16), 0, perp - tan);
		else
			*(v2d *)(gs + oa) = *(const v2d *)(gl + oa) + (perp - tan);
		if (par && d->fj[ob / 16] < d->j0)
			defer_push(d, (int)(ob / 16), 0, perp + tan);
		else
			*(v2d *)(gs + ob) = *(const v2d *)(gl + ob) + (perp + tan);
	}
}

/* Pass 2 over cells k0 <= k < k1 in blocks of KERNEL_WBLOCK (k0 at a
 * block's start): each block's W into wblk if not NULL, and their sum in
 * block order returned. */
static inline __attribute__((always_inline)) double
pass_cells_blocks(const mesh *m, const v2d *r2, const model *p, energy_ws *w, int k0, int k1,
                  double *wblk, const int form)
{
	double W = 0;
	for (int k = k0; k < k1; k += KERNEL_WBLOCK) {
		int ke = k1 - k > KERNEL_WBLOCK ? k + KERNEL_WBLOCK : k1;
		double Wb = form == 0 || form == 3 ? pass_cells_cache(m, r2, p, w, k, ke, 0.0, form) :
		            pass_cells(m, r2, p, w, k, ke, 0.0, form);
		if (wblk)
			wblk[k / KERNEL_WBLOCK] = Wb;
		W += Wb;
	}
	return W;
}

/* form 0, a tissue in cache, where instructions count: the double
 * arrays, the vertices by their byte offsets kjo, the junction vectors
 * kept for the gradient pass; 3 the same by jv when kok = 0.  2, a tissue
 * in memory, where bytes count: the codes, lengths only and the fused
 * gradient pass.  1: a tissue in memory without the codes (kok = 0),
 * lengths only.  tens: dg is not NULL (a constant, so that no junction
 * tests it). */
static inline __attribute__((always_inline)) double
energy_kernel(const mesh *m, const double *r, const model *p, const double *dg,
              double *grad, double *g2max, energy_ws *w, const int form, const int tens,
              const int simd)
{
	const int nj = m->nj;
	const v2d *r2 = (const v2d *)r;
#ifdef ENERGY_HAVE_AVX2
	if (simd && (form == 0 || form == 3))
		pass_lengths4(m, r2, w, 0, nj, form);
	else
#endif
		pass_lengths(m, r2, w, 0, nj, form);
	double W = pass_cells_blocks(m, r2, p, w, 0, m->nc, NULL, form);
	if (grad == NULL)
		return W;
	v2d *g2 = (v2d *)grad;
	if (form == 2) {
		double q2 = 0;
		pass_grad_codes(m, r2, dg, w, g2, 0, nj, g2max, &q2, tens, NULL, 0);
		if (g2max)
			*g2max = q2;
		return W;
	}
	for (int v = 0; v < m->nv; v++)
		g2[v] = (v2d){ 0, 0 };
	pass_grad(m, r2, dg, w, g2, 0, nj, form, tens, NULL, 0);
	if (g2max)
		*g2max = simd ? gmax4(m->nv, g2) : gmax2(m->nv, g2);
	return W;
}

/* The kernel on threads (forms 0 and 2, which have the codes' first and
 * last flags): each thread takes a range of junctions for passes 1 and
 * 3 and a range of the cell blocks for pass 2.  Pass 1 also notes each
 * vertex's first junction; in pass 3 a thread adds in place the terms of
 * the vertices whose first junction lies in its range (their sums run in
 * junction order, as serially), and defers the others, which one thread
 * then adds in the threads' order: every sum the serial kernel's, bit
 * for bit, at any thread count, and W summed in the fixed blocks of
 * pass_cells_blocks. */
typedef struct {
	const mesh *m;
	const double *r;
	const model *p;
	const double *dg;
	double *grad;
	int g2max;      /* the largest force is wanted */
	energy_ws *w;
	int nt;         /* threads that ran */
} par_ctx;

static inline long long part(long long n, int t, int nt)
{
	return n * t / nt;
}

static inline __attribute__((always_inline)) void
par_body(par_ctx *c, int t, int nt, const int form, const int tens, const int simd)
{
	const mesh *m = c->m;
	energy_ws *w = c->w;
	const v2d *r2 = (const v2d *)c->r;
	v2d *g2 = (v2d *)c->grad;
	const int nj = m->nj, nv = m->nv;
	int j0 = (int)part(nj, t, nt), j1 = (int)part(nj, t + 1, nt);
	int v0 = (int)part(nv, t, nt), v1 = (int)part(nv, t + 1, nt);
	if (t == 0)
		c->nt = nt;
#ifdef ENERGY_HAVE_AVX2
	if (simd && form == 0)
		pass_lengths4(m, r2, w, j0, j1, form);
	else
#endif
		pass_lengths(m, r2, w, j0, j1, form);
	if (g2) {
		const unsigned *restrict kjv = m->kjv;
		int *restrict fj = w->fj;
		for (int j = j0; j < j1; j++) {
			unsigned fl = kjv[2 * j + 1] >> MESH_KSHIFT;
			if (fl & MESH_KFIRST_A)
				fj[kjv[2 * j] & MESH_KMASK] = j;
			if (fl & MESH_KFIRST_B)
				fj[kjv[2 * j + 1] & MESH_KMASK] = j;
		}
		if (form == 0)
			for (int v = v0; v < v1; v++)
				g2[v] = (v2d){ 0, 0 };
	}
#pragma omp barrier
	int nb = (m->nc + KERNEL_WBLOCK - 1) / KERNEL_WBLOCK;
	int b0 = (int)part(nb, t, nt), b1 = (int)part(nb, t + 1, nt);
	int k1 = b1 * KERNEL_WBLOCK < m->nc ? b1 * KERNEL_WBLOCK : m->nc;
	if (b0 < b1)
		pass_cells_blocks(m, r2, c->p, w, b0 * KERNEL_WBLOCK, k1, w->wblk, form);
	if (g2 == NULL)
		return;
#pragma omp barrier
	defer d = { .fj = w->fj, .j0 = j0, .n = 0, .cap = w->dcap,
		    .dv = w->dv + (size_t)t * w->dcap, .dt = (v2d *)w->dt + (size_t)t * w->dcap };
	double q2 = 0;
	if (form == 2)
		pass_grad_codes(m, r2, c->dg, w, g2, j0, j1, c->g2max ? &q2 : NULL, &q2, tens, &d, 1);
	else
		pass_grad(m, r2, c->dg, w, g2, j0, j1, form, tens, &d, 1);
	w->dn[t] = d.n;
	w->q2[t] = q2;
#pragma omp barrier
	if (t == 0) {
		int ovf = 0;
		for (int u = 0; u < nt; u++)
			ovf |= w->dn[u] > w->dcap;
		w->ovf = ovf;
		if (ovf) {
			/* out of room: the serial pass */
			for (int u = 0; u < nt; u++)
				w->q2[u] = 0;
			if (form == 2) {
				pass_grad_codes(m, r2, c->dg, w, g2, 0, nj, c->g2max ? &q2 : NULL,
				                w->q2, tens, NULL, 0);
			} else {
				for (int v = 0; v < nv; v++)
					g2[v] = (v2d){ 0, 0 };
				pass_grad(m, r2, c->dg, w, g2, 0, nj, form, tens, NULL, 0);
			}
		} else {
			double q = w->q2[0];
			for (int u = 0; u < nt; u++) {
				const int *dv = w->dv + (size_t)u * w->dcap;
				const v2d *dt = (const v2d *)w->dt + (size_t)u * w->dcap;
				for (int i = 0; i < w->dn[u]; i++) {
					int v = dv[i] >> 1;
					v2d s = g2[v] + dt[i];
					g2[v] = s;
					if (dv[i] & 1) {
						v2d qq = s * s;
						q = qq[0] + qq[1] > q ? qq[0] + qq[1] : q;
					}
				}
			}
			w->q2[0] = q;
		}
	}
	if (form == 2 || !c->g2max)
		return;
#pragma omp barrier
	w->q2[t] = simd ? gmax4(v1 - v0, g2 + v0) : gmax2(v1 - v0, g2 + v0);
}

typedef void par_fn(par_ctx *c, int t, int nt);

#define PAR_BODY(NAME, FORM, TENS, SIMD, ATTR) \
	ATTR static void NAME(par_ctx *c, int t, int nt) { par_body(c, t, nt, FORM, TENS, SIMD); }
PAR_BODY(par_00, 0, 0, 0, )
PAR_BODY(par_01, 0, 1, 0, )
PAR_BODY(par_20, 2, 0, 0, )
PAR_BODY(par_21, 2, 1, 0, )
#ifdef ENERGY_HAVE_AVX2
PAR_BODY(par_00_avx2, 0, 0, 1, __attribute__((target("avx2"))))
PAR_BODY(par_01_avx2, 0, 1, 1, __attribute__((target("avx2"))))
PAR_BODY(par_20_avx2, 2, 0, 1, __attribute__((target("avx2"))))
PAR_BODY(par_21_avx2, 2, 1, 1, __attribute__((target("avx2"))))
#endif
#undef PAR_BODY

static double energy_par(const mesh *m, const double *r, const model *p, const double *dg,
                         double *grad, double *g2max, energy_ws *w, par_fn *fn)
{
	par_ctx c = { .m = m, .r = r, .p = p, .dg = dg, .grad = grad, .g2max = g2max != NULL,
		      .w = w, .nt = 1 };
#pragma omp parallel num_threads(w->nthr)
	{
#ifdef _OPENMP
		fn(&c, omp_get_thread_num(), omp_get_num_threads());
#else
		fn(&c, 0, 1);
#endif
	}
	double W = 0;
	for (int b = 0; b < (m->nc + KERNEL_WBLOCK - 1) / KERNEL_WBLOCK; b++)
		W += w->wblk[b];
	if (g2max) {
		double q = 0;
		for (int t = 0; t < c.nt; t++)
			q = w->q2[t] > q ? w->q2[t] : q;
		*g2max = q;
	}
	return W;
}

/* The kernel's form for this tissue and workspace, its tensions a
 * constant: each of the eight combinations compiled on its own. */
static inline __attribute__((always_inline)) double
energy_select(const mesh *m, const double *r, const model *p, const double *dg,
              double *grad, double *g2max, energy_ws *w, const int simd)
{
	int form = w->vec ? (m->kok ? 0 : 3) : m->kok ? 2 : 1;
	if (w->nthr > 1 && m->nv >= w->par_nv && (form == 0 || form == 2)) {
		par_fn *fn;
#ifdef ENERGY_HAVE_AVX2
		if (simd)
			fn = form == 0 ? (dg ? par_01_avx2 : par_00_avx2) : (dg ? par_21_avx2 : par_20_avx2);
		else
#endif
			fn = form == 0 ? (dg ? par_01 : par_00) : (dg ? par_21 : par_20);
		return energy_par(m, r, p, dg, grad, g2max, w, fn);
	}
	if (dg == NULL)
		return form == 0 ? energy_kernel(m, r, p, NULL, grad, g2max, w, 0, 0, simd) :
		       form == 2 ? energy_kernel(m, r, p, NULL, grad, g2max, w, 2, 0, simd) :
		       form == 3 ? energy_kernel(m, r, p, NULL, grad, g2max, w, 3, 0, simd) :
		                   energy_kernel(m, r, p, NULL, grad, g2max, w, 1, 0, simd);
	return form == 0 ? energy_kernel(m, r, p, dg, grad, g2max, w, 0, 1, simd) :
	       form == 2 ? energy_kernel(m, r, p, dg, grad, g2max, w, 2, 1, simd) :
	       form == 3 ? energy_kernel(m, r, p, dg, grad, g2max, w, 3, 1, simd) :
	                   energy_kernel(m, r, p, dg, grad, g2max, w, 1, 1, simd);
}
static double energy_portable(const mesh *m, const double *r, const model *p,
                              const double *dg, double *grad, double *g2max, energy_ws *w)
{
	return energy_select(m, r, p, dg, grad, g2max, w, 0);
}

/* The same source built for AVX2 as well, and picked at run time: the
 * library's default target (x86-64-v2) has only two-operand SSE, and
 * the three-operand VEX forms save the register copies, 13 % of the
 * step's instructions in cache (bench/RESULTS.md).  FMA is not enabled
 * (target "avx2" does not include it, and ISO C mode does not contract),
 * so both builds do the same operations: the same bits. */
#ifdef ENERGY_HAVE_AVX2
__attribute__((target("avx2"))) static double
energy_avx2(const mesh *m, const double *r, const model *p,
            const double *dg, double *grad, double *g2max, energy_ws *w)
{
	return energy_select(m, r, p, dg, grad, g2max, w, 1);
}
#endif

/* r -= dt f four doubles (two vertices) at a time, two vectors per
 * iteration: with AVX2 one instruction per operation on two vertices,
 * and the loop's own count and branch over four.  Element by element the
 * same product and difference as the scalar loop. */

static inline __attribute__((always_inline)) void
move_body(int nv, double *restrict r, const double *restrict f, double dt)
{
	v4d *restrict r4 = (v4d *)r;
	const v4d *restrict f4 = (const v4d *)f;
	int n = nv / 2, i = 0;
	for (; i + 1 < n; i += 2) {
		r4[i] -= dt * f4[i];
		r4[i + 1] -= dt * f4[i + 1];
	}
	if (i < n)
		r4[i] -= dt * f4[i];
	if (nv & 1)
		((v2d *)r)[nv - 1] -= dt * ((const v2d *)f)[nv - 1];
}

static void move_portable(int nv, double *r, const double *f, double dt)
{
	move_body(nv, r, f, dt);
}

#ifdef ENERGY_HAVE_AVX2
__attribute__((target("avx2"))) static void move_avx2(int nv, double *r, const double *f, double dt)
{
	move_body(nv, r, f, dt);
}
#endif

static void move_one(const energy_ws *w, int nv, double *r, const double *f, double dt)
{
#ifdef ENERGY_HAVE_AVX2
	if (w->simd) {
		move_avx2(nv, r, f, dt);
		return;
	}
#else
	(void)w;
#endif
	move_portable(nv, r, f, dt);
}

/* On threads each takes a range of vertices: element by element the
 * same numbers. */
void mesh_euler_move(const energy_ws *w, int nv, double *r, const double *f, double dt)
{
	if (w->nthr > 1 && nv >= w->par_nv) {
#pragma omp parallel num_threads(w->nthr)
		{
#ifdef _OPENMP
			int t = omp_get_thread_num(), nt = omp_get_num_threads();
			int v0 = (int)part(nv, t, nt), v1 = (int)part(nv, t + 1, nt);
			move_one(w, v1 - v0, r + 2 * (size_t)v0, f + 2 * (size_t)v0, dt);
#endif
		}
		return;
	}
	move_one(w, nv, r, f, dt);
}

int energy_ws_simd(energy_ws *w, int level)
{
	w->simd = 0;
#ifdef ENERGY_HAVE_AVX2
	__builtin_cpu_init();
	if (level >= 1 && __builtin_cpu_supports("avx2"))
		w->simd = 1;
#else
	(void)level;
#endif
	return w->simd;
}

double mesh_energy_force(const mesh *m, const double *r, const model *p,
                         const double *dg, double *grad, double *g2max, energy_ws *w)
{
#ifdef ENERGY_HAVE_AVX2
	if (w->simd)
		return energy_avx2(m, r, p, dg, grad, g2max, w);
#endif
	return energy_portable(m, r, p, dg, grad, g2max, w);
}

double mesh_energy_tension(const mesh *m, const double *r, const model *p,
                           const double *dg, double *grad, energy_ws *w)
{
	return mesh_energy_force(m, r, p, dg, grad, NULL, w);
}

double grad_max_norm(int nv, const double *g)
{
	return sqrt(gmax2(nv, (const v2d *)g));
}
