/* dyn_state.c - the run state of the Euler integrator: saved into the
 * mesh's state lines when a run stops, restored to continue it bit for
 * bit (dynamics.h, dyn_state_save). */
#include "dynamics.h"
#include "dyn_int.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "noise.h"

/* A growing text buffer for one state line. */
typedef struct {
	char *s;
	size_t n, cap;
	int oom;
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void sb_printf(sbuf *b, const char *fmt, ...)
{
	if (b->oom)
		return;
	for (;;) {
		va_list ap;
		va_start(ap, fmt);
		int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
		va_end(ap);
		if (k < 0) {
			b->oom = 1;
			return;
		}
		if (b->s && b->n + (size_t)k < b->cap) {
			b->n += (size_t)k;
			return;
		}
		size_t nc = b->cap ? 2 * b->cap : 256;
		while (nc < b->n + (size_t)k + 1)
			nc *= 2;
		char *q = realloc(b->s, nc);
		if (q == NULL) {
			b->oom = 1;
			return;
		}
		b->s = q;
		b->cap = nc;
	}
}

/* Set state line name to the text in b (none when b is empty: a state
 * line has text) and empty b. */
static int sb_set(mesh *m, const char *name, sbuf *b)
{
	int st = b->oom ? MESH_ENOMEM : b->n ? mesh_state_set(m, name, b->s) : MESH_OK;
	free(b->s);
	*b = (sbuf){ 0 };
	return st;
}

int dyn_state_save(const dyn *d)
{
	mesh *m = d->m;
	sbuf b = { 0 };
	int st;
	/* %a: every double exactly, as a continued run needs it */
	sb_printf(&b, "%a %ld %ld %ld %ld %a %ld %a %a %d", d->c.t, d->c.nstep, d->c.nt1,
	          d->c.nt1_refused, d->c.nsettle, d->c.t_settled, d->nt1_sorted, d->ou_acc,
	          d->fsettle, d->have_lprev);
	/* Optional groups, each only when it or a later one has something to
	 * say (the reader takes them by position): the text of a run that
	 * uses none stays as it was.  The implicit steps', the adaptive
	 * quench's counts, settle_t1's jumps. */
	const int jumps = d->c.nsettle_t1 > 0;
	const int qcounts = d->o.quench == DYN_QUENCH_ADAPTIVE || jumps;
	if (d->o.implicit > 0 || d->impl || qcounts)
		sb_printf(&b, " %d %a %ld %ld %ld %ld %a", d->impl, d->h, d->c.nimpl, d->c.nsolve,
		          d->c.nevent, d->c.nimpl_fail, d->c.t_implicit);
	if (qcounts)
		sb_printf(&b, " %ld %ld", d->c.nevent_expl, d->c.nswitch);
	if (jumps)
		sb_printf(&b, " %ld", d->c.nsettle_t1);
	if ((st = sb_set(m, "dyn_run", &b)) != MESH_OK)
		return st;
	if (d->noise) {
		char rng[OU_STATE_LEN];
		if (ou_state_get(d->noise, rng, sizeof rng) != MESH_OK ||
		    (st = mesh_state_set(m, "dyn_rng", rng)) != MESH_OK)
			return MESH_ENOMEM;
	}
	/* junctions in the integrator's order and orientation (a reader
	 * numbers them afresh from the cells) */
	for (int j = 0; j < m->nj; j++)
		sb_printf(&b, j ? " %d %d" : "%d %d", m->jv[2 * j], m->jv[2 * j + 1]);
	if ((st = sb_set(m, "dyn_junctions", &b)) != MESH_OK)
		return st;
	/* the T1 candidates and their lengths at the last step */
	for (int j = 0; j < m->nj; j++)
		if (d->incand[j])
			sb_printf(&b, b.n ? " %d %a" : "%d %a", j, d->lprev[j]);
	if ((st = sb_set(m, "dyn_t1", &b)) != MESH_OK)
		return st;
	/* coordinates a writer changes by wrapping them into the box */
	for (int v = 0; v < m->nv; v++) {
		double x = m->r[2 * v], y = m->r[2 * v + 1];
		if (!(x >= 0 && x < m->lx && y >= 0 && y < m->ly))
			sb_printf(&b, b.n ? " %d %a %a" : "%d %a %a", v, x, y);
	}
	return sb_set(m, "dyn_r", &b);
}

void dyn_state_clear(mesh *m)
{
	static const char *const names[] = { "dyn_run", "dyn_rng", "dyn_junctions", "dyn_t1",
	                                     "dyn_r" };
	for (size_t n = 0; n < sizeof names / sizeof names[0]; n++)
		mesh_state_del(m, names[n]);
}

static int bad(mesh_error *err, const char *what)
{
	return mesh_error_set(err, 0, MESH_EINVAL, "state %s: not the state of a tis run of this mesh",
	                      what);
}

/* One item "K X1 .. Xn" of a state line: an index K in [0, nmax) into *k
 * and n numbers into x; the text after it and its blanks, or NULL if the
 * item is malformed. */
static const char *next_item(const char *p, long nmax, int n, long *k, double *x)
{
	char *end;
	errno = 0;
	*k = strtol(p, &end, 10);
	if (end == p || errno || *k < 0 || *k >= nmax)
		return NULL;
	for (int i = 0; i < n; i++) {
		p = end;
		x[i] = strtod(p, &end);
		if (end == p)
			return NULL;
	}
	while (*end == ' ')
		end++;
	return end;
}

/* Renumber and orient the junctions as listed in text (pairs a b). */
static int reorder_junctions(mesh *m, const char *text, mesh_error *err)
{
	int nj = m->nj;
	int *perm = malloc((size_t)(nj ? nj : 1) * sizeof *perm);  /* new id of old j */
	int *jv = malloc(2 * (size_t)(nj ? nj : 1) * sizeof *jv);
	int *jc = malloc(2 * (size_t)(nj ? nj : 1) * sizeof *jc);
	double *jimg = malloc(2 * (size_t)(nj ? nj : 1) * sizeof *jimg);
	double *dg = m->dg ? malloc((size_t)(nj ? nj : 1) * sizeof *dg) : NULL;
	mesh_jindex *ix = mesh_jindex_alloc(m);
	int st = MESH_OK;
	if (!perm || !jv || !jc || !jimg || (m->dg && !dg) || !ix) {
		st = mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		goto out;
	}
	for (int j = 0; j < nj; j++)
		perm[j] = -1;
	const char *p = text;
	for (int i = 0; i < nj; i++) {
		char *end;
		errno = 0;
		long a = strtol(p, &end, 10);
		const char *q = end;
		long b = strtol(q, &end, 10);
		if (end == q || errno || a < 0 || b < 0 || a >= m->nv || b >= m->nv) {
			st = bad(err, "dyn_junctions");
			goto out;
		}
		p = end;
		int j = mesh_jindex_find(ix, m, (int)a, (int)b);
		if (j < 0 || perm[j] >= 0) {
			st = bad(err, "dyn_junctions");
			goto out;
		}
		perm[j] = i;
		int flip = m->jv[2 * j] != a;
		jv[2 * i] = (int)a;
		jv[2 * i + 1] = (int)b;
		jc[2 * i] = m->jc[2 * j + flip];
		jc[2 * i + 1] = m->jc[2 * j + !flip];
		jimg[2 * i] = flip ? -m->jimg[2 * j] : m->jimg[2 * j];
		jimg[2 * i + 1] = flip ? -m->jimg[2 * j + 1] : m->jimg[2 * j + 1];
		if (dg)
			dg[i] = m->dg[j];
	}
	while (*p == ' ')
		p++;
	if (*p) {
		st = bad(err, "dyn_junctions");
		goto out;
	}
	for (int i = 0; i < m->coff[m->nc]; i++)
		m->cj[i] = perm[m->cj[i]];
	memcpy(m->jv, jv, 2 * (size_t)nj * sizeof *jv);
	memcpy(m->jc, jc, 2 * (size_t)nj * sizeof *jc);
	memcpy(m->jimg, jimg, 2 * (size_t)nj * sizeof *jimg);
	if (dg)
		memcpy(m->dg, dg, (size_t)nj * sizeof *dg);
	mesh_kernel_build(m);
out:
	mesh_jindex_free(ix);
	free(perm);
	free(jv);
	free(jc);
	free(jimg);
	free(dg);
	return st;
}

int dyn_state_restore_mesh(mesh *m, mesh_error *err)
{
	const char *r = mesh_state_get(m, "dyn_r");
	const char *jo = mesh_state_get(m, "dyn_junctions");
	if (mesh_state_get(m, "dyn_run") == NULL)
		return MESH_OK;
	if (jo == NULL)
		return bad(err, "dyn_junctions");
	long v;
	double xy[2];
	for (const char *p = r ? r : ""; *p;) {
		if ((p = next_item(p, m->nv, 2, &v, xy)) == NULL || !isfinite(xy[0]) || !isfinite(xy[1]))
			return bad(err, "dyn_r");
		m->r[2 * v] = xy[0];
		m->r[2 * v + 1] = xy[1];
	}
	/* image offsets from the exact coordinates, then the run's numbering */
	int st = mesh_build(m, NULL, err);
	if (st != MESH_OK)
		return st;
	return reorder_junctions(m, jo, err);
}

int dyn_state_load(dyn *d, mesh_error *err)
{
	mesh *m = d->m;
	const char *run = mesh_state_get(m, "dyn_run");
	if (run == NULL)
		return MESH_OK;
	dyn_counts c = { 0 };
	long sorted;
	double acc, fs;
	int hl, used = 0, impl = 0, u2 = 0;
	double h = 0;
	if (sscanf(run, "%la %ld %ld %ld %ld %la %ld %la %la %d%n", &c.t, &c.nstep, &c.nt1,
	           &c.nt1_refused, &c.nsettle, &c.t_settled, &sorted, &acc, &fs, &hl, &used) != 10 ||
	    !isfinite(c.t) || !(c.t >= 0) || !isfinite(acc) || !isfinite(fs))
		return bad(err, "dyn_run");
	if (run[used] != '\0' &&
	    (sscanf(run + used, " %d %la %ld %ld %ld %ld %la%n", &impl, &h, &c.nimpl, &c.nsolve,
	            &c.nevent, &c.nimpl_fail, &c.t_implicit, &u2) != 7 ||
	     !(h >= 0 && isfinite(h)) || !isfinite(c.t_implicit)))
		return bad(err, "dyn_run");
	used += u2;
	int u3 = 0;
	if (run[used] != '\0' &&
	    sscanf(run + used, " %ld %ld%n", &c.nevent_expl, &c.nswitch, &u3) != 2)
		return bad(err, "dyn_run");
	used += u3;
	int u4 = 0;
	if (run[used] != '\0' &&
	    (sscanf(run + used, " %ld%n", &c.nsettle_t1, &u4) != 1 || run[used + u4] != '\0'))
		return bad(err, "dyn_run");
	const char *rng = mesh_state_get(m, "dyn_rng");
	if (rng) {
		if (d->noise == NULL && (d->noise = ou_alloc(d->seed)) == NULL)
			return mesh_error_set(err, 0, MESH_ENOMEM, "out of memory");
		if (ou_state_set(d->noise, rng) != MESH_OK)
			return bad(err, "dyn_rng");
	}
	const char *t1 = mesh_state_get(m, "dyn_t1");
	memset(d->incand, 0, (size_t)m->nj);
	long j;
	double l;
	for (const char *p = t1 ? t1 : ""; *p;) {
		if ((p = next_item(p, m->nj, 1, &j, &l)) == NULL || isnan(l))
			return bad(err, "dyn_t1");
		d->incand[j] = 1;
		d->lprev[j] = l;
	}
	d->c = c;
	d->nt1_sorted = sorted;
	d->ou_acc = acc;
	d->fsettle_next = fs;
	d->have_lprev = hl != 0;
	d->impl = impl != 0;
	d->h = h;
	d->cand_ok = 0;
	return MESH_OK;
}
