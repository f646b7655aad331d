/* active_rk.c - the dp5 and bs3 schemes of active junctions (active.h):
 * explicit embedded Runge-Kutta pairs, with
 * error control, located events and the noise on its own time grid.
 *
 * State y = (r, w): the coordinates (2 nv) and, for each of the na active
 * junctions, w_k = (gamma0 + dg_k) l_k, the product that the feedback term
 * conserves (dynamics.h, split).  In w the tension equation loses its
 * singular term:
 *
 *   dr/dt   = -grad W - sum_k dg_k grad l_k,   dg_k = w_k/l_k - gamma0
 *   dw_k/dt = -(w_k - gamma0 l_k)/tau + l_k f_k(t)
 *
 * with f_k the noise forcing, constant on each cell of the grid t = i/N
 * (N = 1/ou_dt cells per time unit) and drawn at the cell's start,
 *
 *   f_k = sigma sqrt(1 - e^{-2 h/tau}) / (tau (1 - e^{-h/tau})) xi_k,
 *
 * the constant forcing over a cell of length h that, without feedback,
 * moves dg from one grid point to the next by the exact OU step
 * (noise.h): the OU statistics at the grid points do not depend on h.
 * The path is a function of the seed and the grid only, so a run refined
 * in rtol converges to the solution for that path.  Steps end on the grid
 * (the forcing jumps there) and f(y) is evaluated again after a draw.
 *
 * Pairs: Dormand-Prince 5(4) (7 stages, FSAL, Shampine's 4th-order dense
 * output) and Bogacki-Shampine 3(2) (4 stages, FSAL, cubic Hermite dense
 * output).  The error is the max norm of the embedded difference over
 * rtol (ACT_ATOL_FACTOR + |y|), coordinates measured from the start of
 * the integrator; the step controller is the usual 0.9 err^(-1/(q+1)),
 * within [0.2, 5].
 *
 * Events are found after each accepted step from the junction lengths at
 * its ends and located on the dense output (events.h) to |l - L| <= rtol
 * L: a T1 where an armed junction shrinks through the threshold, the
 * collapse of an active junction (T1s off), and the re-arming of a
 * junction made by a T1 where it grows through the re-arm length.  At a
 * T1 the step is cut at the event: the state there is the dense output's,
 * every junction below its threshold at that time is T1'd (shortest
 * first; also those that the T1 of a neighbour carried below it, and at
 * a start those already below it), and the next step starts from the
 * changed mesh.
 */
#include "active_int.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "noise.h"
#include "eq1.h"
#include "hold.h"
#include "t1rule.h"
#include "topology.h"
#include "vec2.h"

#define SMAX 7
#define H_START 1e-4
#ifndef PI_BETA
#define PI_BETA 0.04
#endif

typedef struct {
	int s;                  /* stages; the last is f at the step's end */
	int q;                  /* order of the error estimate */
	double c[SMAX];
	double a[SMAX][SMAX];   /* row s - 1: the weights b */
	double e[SMAX];         /* b - bhat */
	int dp5;                /* dense output: Shampine's, else Hermite */
	const char *name;
} tableau;

static const tableau DP5 = {
	7, 4,
	{ 0, 0.2, 0.3, 0.8, 8.0 / 9, 1, 1 },
	{ { 0 },
	  { 0.2 },
	  { 3.0 / 40, 9.0 / 40 },
	  { 44.0 / 45, -56.0 / 15, 32.0 / 9 },
	  { 19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729 },
	  { 9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656 },
	  { 35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84 } },
	{ 71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40 },
	1, "dp5"
};

static const tableau BS3 = {
	4, 2,
	{ 0, 0.5, 0.75, 1 },
	{ { 0 }, { 0.5 }, { 0, 0.75 }, { 2.0 / 9, 1.0 / 3, 4.0 / 9 } },
	{ 2.0 / 9 - 7.0 / 24, 1.0 / 3 - 0.25, 4.0 / 9 - 1.0 / 3, -0.125 },
	0, "bs3"
};

/* Shampine's dense output coefficients for DP5 (Hairer's contd5). */
static const double D5[SMAX] = { -12715105075.0 / 11282082432.0, 0,
				 87487479700.0 / 32700410799.0, -10690763975.0 / 1880347072.0,
				 701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
				 69997945.0 / 29380423.0 };

/* A junction's T1 mode: on the threshold, on the lowered threshold of a
 * junction just made (FRESH), refused, or held (ACT_T1_HOLD: a four-fold
 * vertex, no threshold). */
enum { ARMED, FRESH, REFUSED, HELD };

typedef struct rk rk;

struct rk {
	const tableau *tb;
	int n2, n;
	double *y0, *y1, *yt, *ys, *k[SMAX];
	double *r0;              /* coordinates at the start (error scale) */
	double *dg, *grad, *len; /* rhs scratch: nj tensions, 2 nv, na lengths */
	energy_ws *ws;
	double *force;           /* na: the noise forcing of this cell */
	ou_noise *g;
	double ncell;            /* cells per time unit */
	long kcell;              /* the cell [kcell, kcell + 1) / ncell */
	double h;                /* the next step's length */
	double ts, hs;           /* the last step [ts, ts + hs] (dense output) */
	int have_step;
	unsigned char *mode;     /* nj: ARMED, FRESH, REFUSED */
	unsigned char *fresh;    /* nj: mode == FRESH, for rk_fresh */
	double *thr;             /* nj: T1 (or collapse) length */
	double *l0, *l1;         /* nj: lengths at the event search's start
	                            (per junction: a re-arm moves it) and at
	                            the step's end */
	double *tstart;          /* nj: the time of l0 */
	double *lt;              /* nj: scratch lengths */
	int avx2;                /* the loops' AVX2 build */
	int *t1j, nt1j;          /* the junctions of the last event's T1s */
	/* ACT_T1_HOLD: the held junctions (m->held's, numbered), which of
	 * them could not be resolved (until their pull drops to 0 again),
	 * their pulls at the step's ends, the active index of every junction
	 * (-1: passive), the tensions at a dense sample, and the junctions
	 * made by a T1 not re-armed since (for flip-back counts) */
	int *hj, nh;
	unsigned char *stuck, *t1made;
	double *p0, *p1, *dgs;
	int *ai;
	double hcap;             /* the first step after them at most this */
	int *eidx, *cand;
	double *et0, *eg0, *eg1;
	int failed;
};

/* The loops every right-hand side and every step run are written once
 * for four lanes (GCC's generic vectors) and built twice: for the
 * library's target, where a four-lane operation is two of two lanes, and
 * for AVX2 where the CPU has it (picked at run time as the energy
 * kernel's build is, energy_ws_simd), where it is one.  Each lane does
 * the scalar formula's operations in its order, so both builds give the
 * numbers of the scalar loops, bit for bit. */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(__AVX2__)
#define RK_HAVE_AVX2 1
#include <immintrin.h>   /* declares the AVX builtins */
#endif
/* 256-bit values pass between inlined functions only (GCC's note on the
 * ABI of a 256-bit return is about calls) */
#pragma GCC diagnostic ignored "-Wpsabi"

typedef double v4d __attribute__((vector_size(32), aligned(8)));
typedef long long v4i __attribute__((vector_size(32)));

static inline v2d ld2(const double *p)
{
	return *(const v2d *)p;
}

static inline void st2(double *p, v2d v)
{
	*(v2d *)p = v;
}

static inline __attribute__((always_inline)) v4d ld4(const double *p)
{
	return *(const v4d *)p;
}

static inline __attribute__((always_inline)) void st4(double *p, v4d v)
{
	*(v4d *)p = v;
}

static inline __attribute__((always_inline)) v4d bc4(double x)
{
	return (v4d){ x, x, x, x };
}

/* by lane b > a ? b : a, as v2d_max */
static inline __attribute__((always_inline)) v4d max4(v4d a, v4d b)
{
	v4i gt = b > a;
	return (v4d)(((v4i)b & gt) | ((v4i)a & ~gt));
}

static inline __attribute__((always_inline)) v4d abs4(v4d x)
{
	return (v4d)((v4i)x & (v4i){ 0x7fffffffffffffffLL, 0x7fffffffffffffffLL,
	                             0x7fffffffffffffffLL, 0x7fffffffffffffffLL });
}

/* Four correctly rounded square roots: one vsqrtpd in the AVX2 build
 * (which costs what one of two lanes does; bench/RESULTS.md, the energy
 * kernel's pass 1), two of two lanes otherwise. */
static inline __attribute__((always_inline)) v4d sqrt4(v2d q01, v2d q23, const int wide)
{
#if defined(RK_HAVE_AVX2) && !defined(__clang__)
	if (wide)
		return __builtin_ia32_sqrtpd256((v4d){ q01[0], q01[1], q23[0], q23[1] });
#endif
	(void)wide;
	v2d s01 = v2d_sqrt(q01), s23 = v2d_sqrt(q23);
	return (v4d){ s01[0], s01[1], s23[0], s23[1] };
}

/* The vector of junction j at coordinates y, as junction_vec_sqrt forms it. */
static inline v2d jvec(const int *restrict jv, const double *restrict img, const double *y, int j)
{
	return ld2(y + 2 * jv[2 * j + 1]) - ld2(y + 2 * jv[2 * j]) + ld2(img + 2 * j);
}

/* The lengths of junctions idx[0..n) (idx NULL: 0..n-1) at coordinates y
 * into len[0..n): junction_vec_sqrt's numbers. */
static inline __attribute__((always_inline)) void
jlengths_w(const mesh *m, const double *restrict y, const int *restrict idx, int n,
           double *restrict len, const int wide)
{
	const int *restrict jv = m->jv;
	const double *restrict img = m->jimg;
	int i = 0;
	for (; i + 3 < n; i += 4) {
		v2d d0 = jvec(jv, img, y, idx ? idx[i] : i), d1 = jvec(jv, img, y, idx ? idx[i + 1] : i + 1);
		v2d d2 = jvec(jv, img, y, idx ? idx[i + 2] : i + 2), d3 = jvec(jv, img, y, idx ? idx[i + 3] : i + 3);
		st4(len + i, sqrt4(v2d_hadd(d0 * d0, d1 * d1), v2d_hadd(d2 * d2, d3 * d3), wide));
	}
	for (; i < n; i++) {
		v2d d = jvec(jv, img, y, idx ? idx[i] : i);
		len[i] = v2d_sqrt(v2d_hadd(d * d, d * d))[0];
	}
}

static void jlengths(const mesh *m, const double *restrict y, const int *restrict idx, int n,
                     double *restrict len)
{
	jlengths_w(m, y, idx, n, len, 0);
}

/* The lengths of the active junctions at coordinates y into k->len, their
 * tensions from w into dg (by junction number): what every right-hand
 * side starts with. */
static inline __attribute__((always_inline)) void
tensions_w(act *a, const double *restrict y, double *restrict dg, const int wide)
{
	rk *k = a->s;
	const double g0 = a->o.gamma0, *restrict w = y + k->n2, *restrict len = k->len;
	const int *restrict aj = a->aj;
	const int na = a->na;
	int i = 0;
	if (na == a->m->nj) {
		/* every junction active, aj[i] = i */
		jlengths_w(a->m, y, NULL, na, k->len, wide);
		for (; i + 3 < na; i += 4)
			st4(dg + i, ld4(w + i) / ld4(len + i) - bc4(g0));
	} else {
		jlengths_w(a->m, y, aj, na, k->len, wide);
	}
	for (; i < na; i++)
		dg[aj[i]] = w[i] / len[i] - g0;
	/* a held junction has no length and no tension (hold.h) */
	for (int h = 0; h < k->nh; h++) {
		int j = k->hj[h];
		dg[j] = 0;
		if (k->ai[j] >= 0)
			k->len[k->ai[j]] = 0;
	}
}

static void tensions(act *a, const double *restrict y, double *restrict dg)
{
	tensions_w(a, y, dg, 0);
}

static inline __attribute__((always_inline)) int
rhs_w(act *a, const double *restrict y, double *restrict f, const int wide)
{
	rk *k = a->s;
	const mesh *m = a->m;
	tensions_w(a, y, k->dg, wide);
	mesh_energy_tension(m, y, &a->p, k->dg, k->grad, k->ws);
	if (k->nh > 0)
		hold_grad(m, &a->p, y, k->dg, k->hj, k->nh, k->grad);
	const double *restrict g = k->grad;
	const int n2 = k->n2, na = a->na;
	/* f - f is 0 for a finite f, NaN otherwise: one sum tells */
	v4d bad = { 0, 0, 0, 0 };
	int i = 0;
	for (; i + 3 < n2; i += 4) {
		v4d fi = -ld4(g + i);
		st4(f + i, fi);
		bad += fi - fi;
	}
	double badw = 0;
	for (; i < n2; i++) {
		f[i] = -g[i];
		badw += f[i] - f[i];
	}
	const double g0 = a->o.gamma0, rate = 1 / a->o.tau;
	const double *restrict w = y + n2, *restrict len = k->len, *restrict force = k->force;
	double *restrict fw = f + n2;
	/* four sums of the tests, not one chain through every junction */
	for (i = 0; i + 3 < na; i += 4) {
		v4d fi;
		for (int c = 0; c < 4; c++)
			fi[c] = eq1_dwdt(w[i + c], g0, rate, len[i + c], force[i + c]);
		st4(fw + i, fi);
		bad += fi - fi;
	}
	for (; i < na; i++) {
		double fi = eq1_dwdt(w[i], g0, rate, len[i], force[i]);
		fw[i] = fi;
		badw += fi - fi;
	}
	a->c.nfev++;
	return bad[0] + bad[1] + bad[2] + bad[3] + badw == 0;
}

/* The two builds of NAME_w(act *a, ..., const int wide), and NAME
 * calling the one for the CPU. */
#ifdef RK_HAVE_AVX2
#define RK_BUILDS(type, name, params, ...)                                              \
	static type name##_base params { return name##_w(__VA_ARGS__, 0); }              \
	__attribute__((target("avx2"))) static type name##_avx2 params                   \
	{                                                                                \
		return name##_w(__VA_ARGS__, 1);                                         \
	}                                                                                \
	static type name params                                                          \
	{                                                                                \
		return ((rk *)a->s)->avx2 ? name##_avx2(__VA_ARGS__) : name##_base(__VA_ARGS__); \
	}
#else
#define RK_BUILDS(type, name, params, ...)                                              \
	static type name params { return name##_w(__VA_ARGS__, 0); }
#endif

RK_BUILDS(int, rhs, (act *a, const double *y, double *f), a, y, f)

/* The mesh's state as y, given the lengths l of every active junction
 * (by junction number). */
static void pack(act *a, double *y, const double *l)
{
	rk *k = a->s;
	const mesh *m = a->m;
	memcpy(y, m->r, (size_t)k->n2 * sizeof *y);
	for (int i = 0; i < a->na; i++) {
		int j = a->aj[i];
		y[k->n2 + i] = (a->o.gamma0 + m->dg[j]) * l[j];
	}
}

static void to_mesh(act *a, const double *y)
{
	mesh *m = a->m;
	memcpy(m->r, y, (size_t)((rk *)a->s)->n2 * sizeof *y);
	tensions(a, y, m->dg);
}

/* to_mesh of the state the last right-hand side was taken at (its
 * tensions are in k->dg). */
static void to_mesh_rhs(act *a, const double *y)
{
	rk *k = a->s;
	mesh *m = a->m;
	memcpy(m->r, y, (size_t)k->n2 * sizeof *y);
	for (int i = 0; i < a->na; i++)
		m->dg[a->aj[i]] = k->dg[a->aj[i]];
}

/* Components i..i+3 of the dense output of the last step at theta in
 * [0, 1], each lane the scalar formula's numbers (the state's arrays
 * have 4 components more than the state, so i may be any component). */
static inline __attribute__((always_inline)) v4d dense4(const rk *k, int i, double th)
{
	const tableau *tb = k->tb;
	const v4d y0 = ld4(k->y0 + i), y1 = ld4(k->y1 + i), h = bc4(k->hs), t = bc4(th), one = bc4(1);
	const v4d f0 = ld4(k->k[0] + i), f1 = ld4(k->k[tb->s - 1] + i);
	if (tb->dp5) {
		v4d r2 = y1 - y0, r3 = h * f0 - r2, r4 = r2 - h * f1 - r3, r5 = bc4(0);
		for (int s = 0; s < tb->s; s++)
			r5 += bc4(D5[s]) * ld4(k->k[s] + i);
		r5 *= h;
		return y0 + t * (r2 + (one - t) * (r3 + t * (r4 + (one - t) * r5)));
	}
	v4d dy = y1 - y0;
	return y0 + t * dy + t * (t - one) * ((one - bc4(2) * t) * dy + (t - one) * h * f0 + t * h * f1);
}

/* The whole state on the dense output at theta into y (returned). */
static inline __attribute__((always_inline)) double *
dense_all_w(const act *a, double th, double *y, const int wide)
{
	const rk *k = a->s;
	(void)wide;
	int i = 0;
	for (; i + 3 < k->n; i += 4)
		st4(y + i, dense4(k, i, th));
	if (i < k->n) {
		v4d v = dense4(k, i, th);
		for (int l = 0; i + l < k->n; l++)
			y[i + l] = v[l];
	}
	return y;
}

RK_BUILDS(double *, dense_all, (const act *a, double th, double *y), a, th, y)

static double theta(const rk *k, double t)
{
	double th = (t - k->ts) / k->hs;
	return th < 0 ? 0 : th > 1 ? 1 : th;
}

/* Junction j's length at time t on the dense output (its two vertices'
 * coordinates into ys). */
static double dense_length(act *a, int j, double t)
{
	rk *k = a->s;
	const mesh *m = a->m;
	double th = theta(k, t), d[2];
	int va = m->jv[2 * j], vb = m->jv[2 * j + 1];
	v4d pa = dense4(k, 2 * va, th), pb = dense4(k, 2 * vb, th);
	st2(k->ys + 2 * va, (v2d){ pa[0], pa[1] });
	st2(k->ys + 2 * vb, (v2d){ pb[0], pb[1] });
	return junction_vec_sqrt(m, k->ys, j, d);
}

/* The re-arm length of junction j (0: none). */
static double rearm_length(const act *a, int j)
{
	const rk *k = a->s;
	if (k->mode[j] == REFUSED)
		return a->o.t1_length;
	if (k->mode[j] == FRESH)
		return a->o.t1_rearm;
	return 0;
}

/* Event i: junction i/2 through its threshold (even) or its re-arm
 * length (odd). */
static double event_g(void *data, int i, double t)
{
	act *a = data;
	int j = i >> 1;
	double l = dense_length(a, j, t);
	return l - ((i & 1) ? rearm_length(a, j) : ((rk *)a->s)->thr[j]);
}

/* The threshold of a junction just made by a T1: t1_again t1_new, or
 * the ordinary one for a new junction longer than that. */
static double fresh_threshold(const act *a)
{
	return fmin(a->o.t1_again * a->o.t1_new, a->o.t1_length);
}

static void arm(act *a, int j)
{
	rk *k = a->s;
	k->mode[j] = ARMED;
	k->fresh[j] = 0;
	k->t1made[j] = 0;
	k->thr[j] = a->o.t1_length > 0 ? a->o.t1_length : a->o.l_collapse;
}

/* ---- held four-fold vertices (ACT_T1_HOLD, hold.h) ---- */

/* The held junctions from the mesh's held pairs (a start: what a read
 * mesh holds), each junction's active index. */
static int held_sync(act *a)
{
	rk *k = a->s;
	mesh *m = a->m;
	for (int j = 0; j < m->nj; j++) {
		k->ai[j] = -1;
		k->stuck[j] = 0;
		if (k->mode[j] == HELD) {
			unsigned char t1m = k->t1made[j];
			arm(a, j);
			k->t1made[j] = t1m;
		}
	}
	for (int i = 0; i < a->na; i++)
		k->ai[a->aj[i]] = i;
	k->nh = 0;
	if (m->nheld == 0)
		return MESH_OK;
	if (mesh_held_junctions(m, k->hj) != MESH_OK)
		return MESH_ENOMEM;
	for (int i = 0; i < m->nheld; i++) {
		int j = k->hj[i];
		if (j < 0)
			continue;
		k->mode[j] = HELD;
		k->fresh[j] = 0;
		k->thr[j] = -INFINITY;   /* no threshold crossed */
		k->hj[k->nh++] = j;
	}
	return MESH_OK;
}

/* The larger pull of held junction j at coordinates r, tensions dg (hold.h),
 * which resolution into *w and its direction into dir; the pulling force
 * |F_b - F_a|/2 into *scale. */
static double pull_at(const act *a, const double *r, const double *dg, int j, int *w, double dir[2],
                      double *scale)
{
	hold_forces h;
	if (hold_forces_at(a->m, &a->p, r, dg, j, &h) != MESH_OK) {
		*w = HOLD_REFORM;
		if (dir)
			dir[0] = dir[1] = 0;
		if (scale)
			*scale = 0;
		return -INFINITY;
	}
	double p;
	*w = hold_best(&h, &p);
	if (dir) {
		dir[0] = h.dir[*w][0];
		dir[1] = h.dir[*w][1];
	}
	if (scale)
		*scale = p + h.tnew[*w];
	return p;
}

/* Every held junction's pull at the mesh's state into p (by junction). */
static void pull_ends(const act *a, double *p)
{
	const rk *k = a->s;
	int w;
	for (int h = 0; h < k->nh; h++)
		p[k->hj[h]] = pull_at(a, a->m->r, a->m->dg, k->hj[h], &w, NULL, NULL);
}

static int rk_alloc(act *a, mesh_error *err)
{
	const mesh *m = a->m;
	rk *k = calloc(1, sizeof *k);
	if (k == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	a->s = k;
	k->tb = a->o.scheme == ACT_BS3 ? &BS3 : &DP5;
	k->n2 = 2 * m->nv;
	k->n = k->n2 + a->na;
	size_t n = (size_t)k->n, nj = m->nj ? (size_t)m->nj : 1, na = a->na ? (size_t)a->na : 1;
	int ok = 1;
	/* 4 more than the state: dense4 reads four components from any */
	double **vec[] = { &k->y0, &k->y1, &k->yt, &k->ys, &k->r0, &k->grad };
	for (size_t i = 0; i < sizeof vec / sizeof vec[0]; i++)
		ok &= (*vec[i] = calloc(n + 4, sizeof **vec[i])) != NULL;
	for (int s = 0; s < k->tb->s; s++)
		ok &= (k->k[s] = calloc(n + 4, sizeof *k->k[s])) != NULL;
	double **vj[] = { &k->dg, &k->thr, &k->l0, &k->l1, &k->tstart, &k->lt };
	for (size_t i = 0; i < sizeof vj / sizeof vj[0]; i++)
		ok &= (*vj[i] = calloc(nj, sizeof **vj[i])) != NULL;
	double **ve[] = { &k->et0, &k->eg0, &k->eg1 };
	for (size_t i = 0; i < sizeof ve / sizeof ve[0]; i++)
		ok &= (*ve[i] = calloc(2 * nj, sizeof **ve[i])) != NULL;
	k->len = calloc(na, sizeof *k->len);
	k->force = calloc(na, sizeof *k->force);
	k->mode = calloc(nj, 1);
	k->fresh = calloc(nj, 1);
	k->eidx = calloc(2 * nj, sizeof *k->eidx);
	k->cand = calloc(nj, sizeof *k->cand);
	k->t1j = calloc(nj, sizeof *k->t1j);
	k->hj = calloc(nj, sizeof *k->hj);
	k->ai = calloc(nj, sizeof *k->ai);
	k->stuck = calloc(nj, 1);
	k->t1made = calloc(nj, 1);
	k->p0 = calloc(nj, sizeof *k->p0);
	k->p1 = calloc(nj, sizeof *k->p1);
	k->dgs = calloc(nj, sizeof *k->dgs);
	k->ws = energy_ws_alloc(m);
	/* the kernel's choice of build is this code's too */
	k->avx2 = k->ws && energy_ws_simd(k->ws, 1) == 1;
	if (!ok || !k->len || !k->force || !k->mode || !k->fresh || !k->eidx || !k->cand || !k->t1j || !k->hj ||
	    !k->ai || !k->stuck || !k->t1made || !k->p0 || !k->p1 || !k->dgs || !k->ws)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	if (a->o.sigma > 0 && (k->g = ou_alloc(a->seed)) == NULL)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	k->ncell = round(1 / a->o.ou_dt);
	for (int j = 0; j < m->nj; j++)
		arm(a, j);
	return MESH_OK;
}

static void rk_free(act *a)
{
	rk *k = a->s;
	if (k == NULL)
		return;
	double *v[] = { k->y0, k->y1, k->yt, k->ys, k->r0, k->grad, k->dg, k->thr, k->l0,
			k->l1, k->tstart, k->lt, k->et0, k->eg0, k->eg1, k->len, k->force };
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
		free(v[i]);
	for (int s = 0; s < SMAX; s++)
		free(k->k[s]);
	free(k->mode);
	free(k->fresh);
	free(k->eidx);
	free(k->cand);
	free(k->t1j);
	free(k->hj);
	free(k->ai);
	free(k->stuck);
	free(k->t1made);
	free(k->p0);
	free(k->p1);
	free(k->dgs);
	energy_ws_free(k->ws);
	ou_free(k->g);
	free(k);
}

static const unsigned char *rk_fresh(const act *a)
{
	const rk *k = a->s;
	return k->fresh;
}

static void rk_set_fresh(act *a, const unsigned char *fresh)
{
	rk *k = a->s;
	for (int j = 0; j < a->m->nj; j++) {
		arm(a, j);
		if (fresh && fresh[j]) {
			k->mode[j] = FRESH;
			k->fresh[j] = 1;
			k->thr[j] = fresh_threshold(a);
		}
	}
}

static int rk_rng_get(const act *a, char *buf, size_t n)
{
	const rk *k = a->s;
	if (k->g)
		return ou_state_get(k->g, buf, n);
	if (n < 1)
		return MESH_EDOM;
	buf[0] = '\0';
	return MESH_OK;
}

static int rk_rng_set(act *a, const char *text)
{
	rk *k = a->s;
	if (k->g == NULL || text[0] == '\0')
		return MESH_OK;
	return ou_state_set(k->g, text);
}

/* The lengths the events need at coordinates r (every junction with T1s
 * on, the active ones otherwise) into l, by junction number. */
static void lengths(const act *a, const double *r, double *l)
{
	const mesh *m = a->m;
	if (a->o.t1_length > 0) {
		jlengths(m, r, NULL, m->nj, l);
	} else {
		rk *k = a->s;
		jlengths(m, r, a->aj, a->na, k->lt);
		for (int i = 0; i < a->na; i++)
			l[a->aj[i]] = k->lt[i];
	}
}

/* A fresh start at the mesh's state and time: y0, f(y0), the lengths. */
static int start(act *a)
{
	rk *k = a->s;
	lengths(a, a->m->r, k->l0);
	for (int h = 0; h < k->nh; h++)
		k->l0[k->hj[h]] = 0;
	pull_ends(a, k->p0);
	pack(a, k->y0, k->l0);
	k->have_step = 0;
	a->tprev = a->t;
	for (int j = 0; j < a->m->nj; j++)
		k->tstart[j] = a->t;
	return rhs(a, k->y0, k->k[0]);
}

static void draw(act *a)
{
	rk *k = a->s;
	const double h = 1 / k->ncell, tau = a->o.tau;
	const double amp = a->o.sigma * sqrt(-expm1(-2 * h / tau)) / (tau * -expm1(-h / tau));
	for (int i = 0; i < a->na; i++)
		k->force[i] = amp * ou_gauss(k->g);
}

/* One trial step of length h from y0 into y1 and k[1..s-1]; the error
 * norm (INFINITY if a stage was not finite). */
static inline __attribute__((always_inline)) double trial_w(act *a, double h, const int wide)
{
	rk *k = a->s;
	const tableau *tb = k->tb;
	const int n = k->n, n2 = k->n2;
	const double *restrict y0 = k->y0;
	const v4d hv = bc4(h);
	/* each component summed as the scalar loop sums it (from 0, stage
	 * by stage) */
	for (int s = 1; s < tb->s; s++) {
		double *restrict yt = s == tb->s - 1 ? k->y1 : k->yt;
		const double *as = tb->a[s];
		int i = 0;
		for (; i + 8 <= n; i += 8) {
			v4d c0 = bc4(0), c1 = c0;
			for (int q = 0; q < s; q++) {
				const double *kq = k->k[q] + i;
				const v4d aq = bc4(as[q]);
				c0 += aq * ld4(kq);
				c1 += aq * ld4(kq + 4);
			}
			st4(yt + i, ld4(y0 + i) + hv * c0);
			st4(yt + i + 4, ld4(y0 + i + 4) + hv * c1);
		}
		for (; i < n; i++) {
			double acc = 0;
			for (int q = 0; q < s; q++)
				acc += as[q] * k->k[q][i];
			yt[i] = y0[i] + h * acc;
		}
		if (!rhs_w(a, yt, k->k[s], wide))
			return INFINITY;
	}
	const double rtol = a->o.rtol, atol = ACT_ATOL_FACTOR;
	const double *restrict y1 = k->y1, *restrict r0 = k->r0, *eb = tb->e;
	const v4d rt = bc4(rtol), at = bc4(atol);
	/* two maxima: two chains of divisions in flight; the maximum of
	 * each lane's quotients, NaNs passed over as the scalar loop does */
	v4d e0 = bc4(0), e1 = e0;
	int i = 0;
	for (; i + 8 <= n; i += 8) {
		v4d c0 = bc4(0), c1 = c0;
		for (int q = 0; q < tb->s; q++) {
			const double *kq = k->k[q] + i;
			const v4d eq = bc4(eb[q]);
			c0 += eq * ld4(kq);
			c1 += eq * ld4(kq + 4);
		}
		v4d u0 = ld4(y0 + i), u1 = ld4(y1 + i), w0 = ld4(y0 + i + 4), w1 = ld4(y1 + i + 4);
		if (i + 8 <= n2) {
			u0 -= ld4(r0 + i);
			u1 -= ld4(r0 + i);
			w0 -= ld4(r0 + i + 4);
			w1 -= ld4(r0 + i + 4);
		} else if (i < n2) {
			/* the block where the coordinates end */
			for (int c = 0; c < 4; c++) {
				double ra = i + c < n2 ? r0[i + c] : 0, rb = i + 4 + c < n2 ? r0[i + 4 + c] : 0;
				if (i + c < n2) {
					u0[c] -= ra;
					u1[c] -= ra;
				}
				if (i + 4 + c < n2) {
					w0[c] -= rb;
					w1[c] -= rb;
				}
			}
		}
		e0 = max4(e0, abs4(hv * c0) / (rt * (at + max4(abs4(u0), abs4(u1)))));
		e1 = max4(e1, abs4(hv * c1) / (rt * (at + max4(abs4(w0), abs4(w1)))));
	}
	e0 = max4(e0, e1);
	double e = 0;
	for (int c = 0; c < 4; c++)
		e = e0[c] > e ? e0[c] : e;
	for (; i < n; i++) {
		double acc = 0;
		for (int q = 0; q < tb->s; q++)
			acc += eb[q] * k->k[q][i];
		double u0 = y0[i], u1 = y1[i];
		if (i < n2) {
			u0 -= r0[i];
			u1 -= r0[i];
		}
		double sc = rtol * (atol + fmax(fabs(u0), fabs(u1)));
		double ei = fabs(h * acc) / sc;
		e = ei > e ? ei : e;
	}
	return isfinite(e) ? e : INFINITY;
}

RK_BUILDS(double, trial, (act *a, double h), a, h)

/* ACT_T1_HOLD: resolve the held junction with the largest positive pull
 * at the mesh's state (none stuck); 1 done, 0 none, -1 out of memory. */
static int resolve_one(act *a, mesh_error *err)
{
	rk *k = a->s;
	mesh *m = a->m;
	int best = -1, w = 0, bw = 0;
	double pb = 0, dir[2], bdir[2] = { 0, 0 };
	for (int h = 0; h < k->nh; h++) {
		int j = k->hj[h];
		if (k->stuck[j])
			continue;
		double p = pull_at(a, m->r, m->dg, j, &w, dir, NULL);
		if (p > pb || (p == pb && p > 0 && j < best)) {
			pb = p;
			best = j;
			bw = w;
			bdir[0] = dir[0];
			bdir[1] = dir[1];
		}
	}
	if (best < 0)
		return 0;
	t1_nbhd nb;
	mesh_error e2;
	if (mesh_t1_nbhd(m, best, &nb, &e2) != MESH_OK) {
		k->stuck[best] = 1;
		return 1;
	}
	int touched[5];
	int st = hold_resolve(m, best, bw, bdir, a->o.t1_new, touched, &e2);
	if (st == MESH_ENOMEM) {
		mesh_error_set(err, 0, st, "out of memory");
		return -1;
	}
	if (st != MESH_OK) {
		/* not now: again once its pull has dropped and risen */
		k->stuck[best] = 1;
		return 1;
	}
	for (int h = 0; h < k->nh; h++)
		if (k->hj[h] == best) {
			k->hj[h] = k->hj[--k->nh];
			break;
		}
	int lose[2] = { -1, -1 }, gain[2] = { -1, -1 };
	if (bw == HOLD_T1) {
		a->c.nt1++;
		a->c.nt1_again += k->t1made[best];
		lose[0] = nb.L;
		lose[1] = nb.R;
		gain[0] = nb.Ca;
		gain[1] = nb.Cb;
	} else {
		a->c.nreform++;
		gain[0] = nb.L;
		gain[1] = nb.R;
	}
	/* made by a T1 now, or as it was before it collapsed */
	int made = bw == HOLD_T1 ? 1 : k->t1made[best];
	k->mode[best] = FRESH;
	k->fresh[best] = 1;
	k->thr[best] = fresh_threshold(a);
	k->t1made[best] = (unsigned char)made;
	k->t1j[k->nt1j++] = best;
	if (a->hook)
		a->hook(a->hook_data, a->t, best, lose, gain, 0, bw == HOLD_T1 ? ACT_EV_T1 : ACT_EV_REFORM, pb);
	for (int e = 0; e < 5; e++)
		jlengths(m, m->r, touched + e, 1, k->lt + touched[e]);
	return 1;
}

/* The T1s (ACT_T1_PAPER) or collapses (ACT_T1_HOLD) of every junction that
 * is below its threshold now (the mesh is at the event or a start),
 * shortest first, as the paper's rule says: the one whose event was found,
 * others that crossed at the same time, and those that a T1 next to them
 * carried below the threshold (the vertices of the T1'd junction jump);
 * then, ACT_T1_HOLD, the resolutions of held vertices pulled apart, the
 * one pulled harder first (one just made too), and again.  The junctions
 * made in k->t1j.  Returns their number, -1 out of memory. */
static int events_at(act *a, mesh_error *err)
{
	rk *k = a->s;
	mesh *m = a->m;
	const int hold = a->o.t1_rule == ACT_T1_HOLD;
	double *lt = k->lt;
	k->nt1j = 0;
	/* every length once, then only those a T1 changed */
	jlengths(m, m->r, NULL, m->nj, lt);
	for (;;) {
		int best = -1;
		double lb = INFINITY;
		for (int j = 0; j < m->nj; j++) {
			double l = lt[j];
			if (l < k->thr[j] && t1_first(l, j, lb, best)) {
				lb = l;
				best = j;
			}
		}
		if (best < 0) {
			int r = hold ? resolve_one(a, err) : 0;
			if (r < 0)
				return -1;
			if (r > 0)
				continue;
			return k->nt1j;
		}
		int lose[2], touched[5];
		mesh_error e2;
		int st;
		if (hold) {
			t1_nbhd nb;
			st = mesh_t1_nbhd(m, best, &nb, &e2);
			if (st == MESH_OK && (st = hold_collapse(m, best, &e2)) == MESH_OK) {
				const int t5[5] = { best, nb.jpa, nb.jat, nb.jbq, nb.jsb };
				memcpy(touched, t5, sizeof t5);
				lose[0] = nb.L;
				lose[1] = nb.R;
			}
		} else {
			st = t1_do(m, best, a->o.t1_new, lose, touched);
		}
		if (st == MESH_ENOMEM) {
			mesh_error_set(err, 0, st, "out of memory");
			return -1;
		}
		if (st != MESH_OK) {
			/* not allowed: tried again if it shrinks to half this, or
			 * as any junction once it has grown past the threshold */
			a->c.nt1_refused++;
			k->mode[best] = REFUSED;
			k->fresh[best] = 0;
			k->thr[best] = 0.5 * lb;
			continue;
		}
		if (hold) {
			a->c.nhold++;
			k->mode[best] = HELD;
			k->fresh[best] = 0;
			k->thr[best] = -INFINITY;
			k->stuck[best] = 0;
			k->hj[k->nh++] = best;
			int w;
			double p = pull_at(a, m->r, m->dg, best, &w, NULL, NULL);
			const int gain[2] = { -1, -1 };
			if (a->hook)
				a->hook(a->hook_data, a->t, best, lose, gain, lb, ACT_EV_HOLD, p);
		} else {
			k->t1j[k->nt1j++] = best;
			a->c.nt1++;
			a->c.nt1_again += k->mode[best] == FRESH;
			k->mode[best] = FRESH;
			k->fresh[best] = 1;
			k->thr[best] = fresh_threshold(a);
			if (a->hook)
				a->hook(a->hook_data, a->t, best, lose, m->jc + 2 * best, lb, ACT_EV_T1, NAN);
		}
		for (int e = 0; e < 5; e++)
			jlengths(m, m->r, touched + e, 1, lt + touched[e]);
	}
}

/* The step cut at the event at t (of junction j, -1 a held vertex's): the
 * state there in the mesh. */
static int cut(act *a, double t, int j, double *tev)
{
	rk *k = a->s;
	*tev = t;
	dense_all(a, theta(k, t), k->yt);
	to_mesh(a, k->yt);
	k->cand[0] = j;
	return 1;
}

/* Event j: held junction j's larger pull on the dense output at t. */
static double pull_g(void *data, int j, double t)
{
	act *a = data;
	rk *k = a->s;
	dense_all(a, theta(k, t), k->ys);
	tensions(a, k->ys, k->dgs);
	int w;
	return pull_at(a, k->ys, k->dgs, j, &w, NULL, NULL);
}

/* The events of the step just taken (y0 at k->ts to y1 at t1): re-arms
 * are applied where they happen; the first T1 or collapse cuts the step
 * there (*tev, 1 returned), the state at it in the mesh. */
static int step_events(act *a, double t1, double *tev)
{
	rk *k = a->s;
	const mesh *m = a->m;
	const int t1on = a->o.t1_length > 0, nj = t1on ? m->nj : a->na;
	const double ttol = 4 * DBL_EPSILON * fabs(t1);
	/* the step's last right-hand side was taken at its end: the active
	 * junctions' lengths are those */
	if (t1on && a->na < m->nj) {
		lengths(a, k->y1, k->l1);
	} else {
		for (int i = 0; i < a->na; i++)
			k->l1[a->aj[i]] = k->len[i];
	}
	/* the first held vertex pulled apart in the step: its pull crossing 0
	 * upwards, located to rtol of the pulling force */
	double tres = INFINITY;
	if (k->nh > 0) {
		int n = 0;
		double ftol = INFINITY;
		pull_ends(a, k->p1);
		for (int h = 0; h < k->nh; h++) {
			int j = k->hj[h], w;
			if (k->stuck[j] && !(k->p1[j] > 0))
				k->stuck[j] = 0;
			if (k->stuck[j] || !ev_crossed(k->p0[j], k->p1[j], 1))
				continue;
			double sc;
			pull_at(a, m->r, m->dg, j, &w, NULL, &sc);
			ftol = fmin(ftol, a->o.rtol * sc);
			k->eidx[n] = j;
			k->et0[n] = k->ts;
			k->eg0[n] = k->p0[j];
			k->eg1[n++] = k->p1[j];
		}
		int which;
		if (n > 0)
			ev_first(pull_g, a, k->eidx, k->et0, k->eg0, k->eg1, n, t1, ftol, ttol, &which, &tres);
	}
	for (;;) {
		int n = 0;
		for (int q = 0; q < nj; q++) {
			int j = t1on ? q : a->aj[q];
			double thr = k->thr[j], ra = t1on ? rearm_length(a, j) : 0;
			if (ev_crossed(k->l0[j] - thr, k->l1[j] - thr, -1)) {
				k->eidx[n] = 2 * j;
				k->et0[n] = k->tstart[j];
				k->eg0[n] = k->l0[j] - thr;
				k->eg1[n++] = k->l1[j] - thr;
			} else if (ra > 0 && ev_crossed(k->l0[j] - ra, k->l1[j] - ra, 1)) {
				k->eidx[n] = 2 * j + 1;
				k->et0[n] = k->tstart[j];
				k->eg0[n] = k->l0[j] - ra;
				k->eg1[n++] = k->l1[j] - ra;
			}
		}
		if (n == 0 && tres == INFINITY)
			return 0;
		if (n == 0)
			return cut(a, tres, -1, tev);
		/* the tolerance of the shortest of the candidates' lengths (a
		 * junction on its lowered threshold, 0.9 t1_new, beside others on
		 * the threshold: each is located within rtol of its own) */
		int which;
		double t, lev = INFINITY;
		for (int c = 0; c < n; c++) {
			int ic = k->eidx[c];
			double lc = (ic & 1) ? rearm_length(a, ic >> 1) : k->thr[ic >> 1];
			lev = lc < lev ? lc : lev;
		}
		double ltol = a->o.rtol * lev;
		ev_first(event_g, a, k->eidx, k->et0, k->eg0, k->eg1, n, t1, ltol, ttol, &which, &t);
		int i = k->eidx[which], j = i >> 1;
		if (tres < t)
			return cut(a, tres, -1, tev);
		if (i & 1) {
			/* a re-arm: from here on j is an armed junction */
			arm(a, j);
			k->tstart[j] = t;
			k->l0[j] = dense_length(a, j, t);
			continue;
		}
		return cut(a, t, j, tev);
	}
}

/* The first step after the T1s of an event (f at the new state in
 * k[0]): a T1 makes a junction t1_new long whose vertices move fast, and
 * the step the trajectory before it allowed is often far too long there
 * (at the storm point 4 in 10 such steps were rejected, most by a factor
 * of 10^3).  A step that moves the two ends of a new junction of length L
 * by more than about L/3 relative to each other is rejected more often
 * than not (dp5 at rtol 1e-6: 3 % of first steps below L/3, 57 % at
 * L/1.8, 98 % at L), so it is at most T1_STEP L/|v_b - v_a|
 * (rtol/1e-6)^(1/(q+1)) for each new junction (q + 1 the order of the
 * error estimate's step), T1_STEP from the right-hand sides per T1 at
 * the storm point (0.05: 11.9, 0.1: 9.8, 0.15: 9.4, 0.2: 9.6, 0.3: 9.7,
 * 0.4: 10.2, none: 11.4, over t 2-3). */
#define T1_STEP 0.15
static double t1_step(const act *a)
{
	const rk *k = a->s;
	const mesh *m = a->m;
	const double *f = k->k[0];
	double h = INFINITY;
	for (int i = 0; i < k->nt1j; i++) {
		int j = k->t1j[i], va = m->jv[2 * j], vb = m->jv[2 * j + 1];
		double dx = f[2 * vb] - f[2 * va], dy = f[2 * vb + 1] - f[2 * va + 1];
		double v = sqrt(dx * dx + dy * dy);
		if (v > 0 && k->l0[j] > 0 && k->l0[j] / v < h)
			h = k->l0[j] / v;
	}
	return T1_STEP * h * pow(a->o.rtol / 1e-6, 1.0 / (k->tb->q + 1));
}

/* One segment to t_seg (a checkpoint or the end) or an event: the
 * integrator starts afresh from the mesh's state (what a run read from
 * the mesh written there does). */
static int rk_segment(act *a, double t_seg, mesh_error *err)
{
	act_end *why = &a->why;
	rk *k = a->s;
	const tableau *tb = k->tb;
	*why = ACT_END_TIME;
	if (k->failed) {
		*why = ACT_END_NONFINITE;
		return MESH_OK;
	}
	/* a restart, as from a mesh read at this time: refused T1s are
	 * forgotten (the mesh does not record them) */
	for (int j = 0; j < a->m->nj; j++)
		if (k->mode[j] == REFUSED)
			arm(a, j);
	if (held_sync(a) != MESH_OK)
		return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
	memcpy(k->r0, a->m->r, (size_t)k->n2 * sizeof *k->r0);
	double c = a->t * k->ncell;
	k->kcell = (long)floor(c);
	if (k->g)
		draw(a);
	/* a junction below its threshold at a start (a refused one, armed
	 * again; one shorter than the threshold in the mesh) is T1'd now, as
	 * at an event */
	if (a->o.t1_length > 0 && events_at(a, err) < 0)
		return MESH_ENOMEM;
	if (!start(a))
		goto nonfinite;
	k->h = H_START;
	/* PI control (Hairer's DOPRI5: beta 0.04 damps the step's
	 * oscillation on the stability boundary, where a stiff network runs) */
	const double expo = -1.0 / (tb->q + 1), beta = PI_BETA;
	double eold = 1e-4;
	int rejected = 0, post = 0;
	while (a->t < t_seg) {
		double tend = t_seg;
		if (k->g) {
			double tc = (double)(k->kcell + 1) / k->ncell;
			tend = tc < tend ? tc : tend;
		}
		double h = post && k->hcap < k->h ? k->hcap : k->h, t1 = a->t + h;
		int land = 0;
		if (t1 >= tend - 0.01 * h) {
			h = tend - a->t;
			t1 = tend;
			land = 1;
		}
		double e = trial(a, h);
		if (!(e <= 1)) {
			a->c.nreject++;
			double fac = isfinite(e) ? fmax(0.2, 0.9 * pow(e, expo)) : 0.25;
			k->h = h * fmin(fac, 1.0);
			rejected = 1;
			if (!(k->h > 1e-14 * (1 + fabs(a->t))))
				goto nonfinite;
			continue;
		}
		double ee = e > 1e-10 ? e : 1e-10;
		double fac = fmin(5.0, fmax(0.2, 0.9 * pow(ee, expo + 0.75 * beta) * pow(eold, beta)));
		eold = ee > 1e-4 ? ee : 1e-4;
		if (rejected)
			fac = fmin(fac, 1.0);
		rejected = 0;
		double hn = h * fac;
		k->h = land && hn < k->h ? k->h : hn;
		post = 0;
		a->c.nstep++;
		k->ts = a->t;
		k->hs = h;
		k->have_step = 1;
		a->tprev = a->t;
		a->t = t1;
		to_mesh_rhs(a, k->y1);
		double tev;
		int nc = step_events(a, t1, &tev);
		if (nc > 0) {
			a->t = tev;
			if (a->o.t1_length == 0) {
				a->c.jcollapse = k->cand[0];
				*why = ACT_END_COLLAPSE;
				if (a->obs)
					a->obs(a, a->obs_data);
				return MESH_OK;
			}
			int quit = a->obs && a->obs(a, a->obs_data);
			if (events_at(a, err) < 0)
				return MESH_ENOMEM;
			if (tev == tend && k->g && tev < t_seg) {
				k->kcell++;
				draw(a);
			}
			if (!start(a))
				goto nonfinite;
			post = 1;
			k->hcap = t1_step(a);
			if (quit) {
				*why = ACT_END_STOP;
				return MESH_OK;
			}
			continue;
		}
		int quit = a->obs && a->obs(a, a->obs_data);
		/* FSAL: the last stage is f at the new start */
		double *sw = k->y0;
		k->y0 = k->y1;
		k->y1 = sw;
		sw = k->k[0];
		k->k[0] = k->k[tb->s - 1];
		k->k[tb->s - 1] = sw;
		sw = k->l0;
		k->l0 = k->l1;
		k->l1 = sw;
		sw = k->p0;
		k->p0 = k->p1;
		k->p1 = sw;
		for (int j = 0; j < a->m->nj; j++)
			k->tstart[j] = t1;
		k->have_step = 0;
		if (land && k->g && t1 == tend && t1 < t_seg) {
			k->kcell++;
			draw(a);
			if (!rhs(a, k->y0, k->k[0]))
				goto nonfinite;
		}
		if (quit) {
			*why = ACT_END_STOP;
			return MESH_OK;
		}
	}
	return MESH_OK;
nonfinite:
	k->failed = 1;
	*why = ACT_END_NONFINITE;
	mesh_error_set(err, 0, MESH_EDOM, "the %s step failed at t = %.6g (step size %.3g)",
		       tb->name, a->t, k->h);
	return MESH_OK;
}

static int rk_sample(act *a, double t, double *r, double *dg)
{
	rk *k = a->s;
	const mesh *m = a->m;
	if (!k->have_step || t >= a->t || t < a->tprev) {
		memcpy(r, m->r, (size_t)k->n2 * sizeof *r);
		memcpy(dg, m->dg, (size_t)m->nj * sizeof *dg);
		return MESH_OK;
	}
	double th = theta(k, t);
	dense_all(a, th, k->ys);
	memset(dg, 0, (size_t)m->nj * sizeof *dg);
	memcpy(r, k->ys, (size_t)k->n2 * sizeof *r);
	tensions(a, k->ys, dg);
	return MESH_OK;
}

static int rk_run(act *a, double t_end, volatile sig_atomic_t *stop, act_end *why,
                  mesh_error *err)
{
	mesh_keep_wrapped(a->m);
	return act_segments(a, t_end, stop, why, err);
}

/* The junctions were renumbered: every one armed, as a read mesh's. */
static int rk_renumbered(act *a, mesh_error *err)
{
	(void)err;
	rk_set_fresh(a, NULL);
	return MESH_OK;
}

const act_ops act_rk_ops = {
	.alloc = rk_alloc, .free = rk_free, .run = rk_run, .segment = rk_segment,
	.sample = rk_sample, .rng_get = rk_rng_get, .rng_set = rk_rng_set,
	.fresh = rk_fresh, .set_fresh = rk_set_fresh, .renumbered = rk_renumbered,
	.counted = NULL
};
