/* anneal.c - the sample preparation protocol (anneal.h). */
#include "anneal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "order.h"

void anneal_opts_init(anneal_opts *o)
{
	*o = (anneal_opts){ .relax = 1000, .seed = 1, .log_every = 1 };
	dyn_opts_init(&o->d);
	o->d.tau = 1;
	o->d.settle = ANNEAL_SETTLE_DEFAULT;
	o->d.ou_dt = ANNEAL_OUDT_DEFAULT;
	o->d.dt_max = o->d.dr_max = ANNEAL_DT_DEFAULT;
	o->d.t1_again = ANNEAL_T1AGAIN_DEFAULT;
	o->d.quench = DYN_QUENCH_ADAPTIVE;
}

void anneal_opts_paper(anneal_opts *o)
{
	o->d.dt_max = 1e-3;
	o->d.dr_max = 1e-3;
	o->d.ou_dt = ANNEAL_PAPER_OUDT;
	o->d.settle = ANNEAL_SETTLE_DEFAULT;
	o->d.quench = DYN_QUENCH_EULER;
	o->d.implicit = 0;
	o->d.t1_again = 0;
	o->d.settle_t1 = 0;
}

void anneal_default_stages(anneal_opts *o, double quench)
{
	o->sig[0] = 0.5;
	o->dur[0] = 3000;
	o->sig[1] = quench;
	o->dur[1] = 7000;
	o->nstage = 2;
}

void anneal_protocol(const anneal_opts *o, const model *p, char *buf, size_t n)
{
	/* stages as one token, "SIGMA:DURATION,..." (each number exact) */
	char st[ANNEAL_MAXSTAGE * 64 + 8] = "";
	for (int i = 0; i < o->nstage; i++) {
		char a[48] = "", b[48] = "";
		mesh_run_key_num(a, sizeof a, "s", o->sig[i]);
		mesh_run_key_num(b, sizeof b, "d", o->dur[i]);
		size_t len = strlen(st);
		snprintf(st + len, sizeof st - len, "%s%s:%s", i ? "," : "", a + 2, b + 2);
	}
	buf[0] = '\0';
	mesh_run_key(buf, n, "stages", o->nstage ? st : "none");
	mesh_run_key_num(buf, n, "relax", o->relax);
	mesh_run_key_num(buf, n, "tau", o->d.tau);
	snprintf(st, sizeof st, "%lu", o->seed);
	mesh_run_key(buf, n, "seed", st);
	mesh_run_key_num(buf, n, "dt", o->d.dt_max);
	mesh_run_key_num(buf, n, "dr", o->d.dr_max);
	mesh_run_key_num(buf, n, "ou_dt", o->d.ou_dt);
	mesh_run_key_num(buf, n, "settle", o->d.settle);
	mesh_run_key_num(buf, n, "t1", o->d.t1_length);
	mesh_run_key_num(buf, n, "t1_new", o->d.t1_new);
	mesh_run_key_num(buf, n, "implicit", o->d.implicit);
	mesh_run_key_num(buf, n, "t1_again", o->d.t1_again);
	mesh_run_key(buf, n, "quench", dyn_quench_name(o->d.quench));
	/* only when on: the protocols of meshes made before it stay valid */
	if (o->d.settle_t1)
		mesh_run_key(buf, n, "settle_t1", "1");
	mesh_run_key_num(buf, n, "p0", p->p0);
	mesh_run_key_num(buf, n, "ka", p->ka);
}

int anneal_resume(mesh *m, const model *p, const anneal_opts *o, int *continued,
                  mesh_error *err)
{
	char proto[2048];
	anneal_protocol(o, p, proto, sizeof proto);
	const char *name = o->name ? o->name : "<mesh>";
	mesh_error e2;
	if (mesh_run_check(m, "tis-anneal", proto, continued, &e2) != MESH_OK)
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", name, e2.msg);
	if (*continued && mesh_state_get(m, "dyn_run") == NULL)
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: state run without state dyn_run: not "
		                      "the state of a tis run of this mesh", name);
	if (*continued && dyn_state_restore_mesh(m, &e2) != MESH_OK)
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", name, e2.msg);
	return MESH_OK;
}

/* A run in progress. */
struct run {
	const anneal_opts *o;
	const anneal_io *io;
	mesh *m;
	dyn *d;
	anneal_status s;
	double next_frame, next_log;
	long kframe, klog;
	int io_stop;         /* the log callback asked to stop */
};

static void status(struct run *u, int energy)
{
	const mesh *m = u->m;
	int n = 0;
	for (int k = 0; k < m->nc; k++)
		n += m->coff[k + 1] - m->coff[k] == 6;
	dyn_counts_get(u->d, &u->s.c);
	u->s.f6 = (double)n / m->nc;
	u->s.energy = energy ? dyn_energy(u->d) : 0;
}

static void log_row(struct run *u)
{
	if (u->io->log == NULL || u->io_stop)
		return;
	status(u, 1);
	u->io_stop = u->io->log(u->io->data, &u->s);
}

/* After every step: frames, log rows and progress at the first step at or
 * after their time, so that watching does not change the run. */
static int observe(dyn *d, void *data)
{
	struct run *u = data;
	dyn_counts c;
	dyn_counts_get(d, &c);
	if (u->o->every > 0 && c.t >= u->next_frame) {
		/* the final mesh is the frame at the end: not twice */
		if (c.t < u->s.total * (1 - 1e-12) && u->io->frame)
			u->io->frame(u->io->data, u->m, c.t);
		while (u->next_frame <= c.t)
			u->next_frame = ++u->kframe * u->o->every;
	}
	if (u->io->log && c.t >= u->next_log) {
		log_row(u);
		while (u->next_log <= c.t)
			u->next_log = ++u->klog * u->o->log_every;
	}
	if (u->io->step && (c.nstep & 4095) == 0) {
		status(u, 0);
		u->io->step(u->io->data, &u->s);
	}
	return u->io_stop;
}

/* Run to cumulative time t_end: 1 if it got there. */
static int run_to(struct run *u, double t_end, volatile sig_atomic_t *stop, anneal_result *r,
                  mesh_error *err, int *st)
{
	*st = dyn_run(u->d, t_end, stop, observe, u, err);
	if (*st == MESH_ENOMEM)
		return 0;
	r->why = *st != MESH_OK ? ANNEAL_END_FAILED : u->io_stop ? ANNEAL_END_IO
		: stop && *stop ? ANNEAL_END_STOP : ANNEAL_END_DONE;
	*st = MESH_OK;
	return r->why == ANNEAL_END_DONE;
}

/* With t1_again > 0 the junctions a T1 made that have not yet been
 * longer than the threshold decide which T1s are done (dynamics.h), and
 * dyn's state lines do not hold them: a stopped run lists them (in the
 * integrator's numbering, which dyn_junctions restores). */
static int fresh_save(const dyn *d, mesh *m)
{
	const unsigned char *f = dyn_fresh(d);
	size_t cap = 16 * (size_t)(m->nj + 1), len = 0;
	char *s = malloc(cap);
	if (s == NULL)
		return MESH_ENOMEM;
	s[0] = '\0';
	for (int j = 0; j < m->nj; j++)
		if (f[j])
			len += (size_t)snprintf(s + len, cap - len, len ? " %d" : "%d", j);
	int st = len ? mesh_state_set(m, "anneal_fresh", s) : MESH_OK;
	free(s);
	return st;
}

static int fresh_load(dyn *d, mesh *m)
{
	const char *t = mesh_state_get(m, "anneal_fresh");
	unsigned char *f = calloc((size_t)(m->nj ? m->nj : 1), 1);
	if (f == NULL)
		return MESH_ENOMEM;
	int st = MESH_OK;
	for (const char *p = t ? t : ""; *p && st == MESH_OK;) {
		char *end;
		long j = strtol(p, &end, 10);
		if (end == p || j < 0 || j >= m->nj)
			st = MESH_EINVAL;
		else
			f[j] = 1;
		p = end;
		while (*p == ' ')
			p++;
	}
	if (st == MESH_OK)
		dyn_set_fresh(d, f);
	free(f);
	return st;
}

int anneal_run(mesh *m, const model *p, const anneal_opts *o, int continued,
               volatile sig_atomic_t *stop, const anneal_io *io, anneal_result *r,
               mesh_error *err)
{
	static const anneal_io none = { 0 };
	struct run u = { .o = o, .io = io ? io : &none, .m = m };
	*r = (anneal_result){ .continued = continued };
	for (int i = 0; i < o->nstage; i++)
		u.s.total += o->dur[i];
	u.s.total += o->relax;
	int st = dyn_alloc(m, p, &o->d, o->seed, &u.d, err);
	if (st != MESH_OK)
		return st;
	mesh_error e2;
	if (continued && dyn_state_load(u.d, &e2) != MESH_OK) {
		dyn_free(u.d);
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: %s", o->name ? o->name : "<mesh>", e2.msg);
	}
	if (continued && o->d.t1_again > 0 && fresh_load(u.d, m) != MESH_OK) {
		dyn_free(u.d);
		return mesh_error_set(err, 0, MESH_EINVAL, "%s: state anneal_fresh: not the state of "
		                      "a tis run of this mesh", o->name ? o->name : "<mesh>");
	}
	/* used up: frames and the final mesh carry only a new one */
	dyn_state_clear(m);
	mesh_state_del(m, "run");
	mesh_state_del(m, "anneal_fresh");
	dyn_counts_get(u.d, &r->c0);
	/* frames and log rows at the first step at or after each multiple of
	 * their interval; a continued run goes on with the next one */
	/* a continued run's start is the end of the run it continues, which
	 * logged the rows up to it */
	if (!continued)
		log_row(&u);
	do
		u.next_log = ++u.klog * o->log_every;
	while (u.next_log <= r->c0.t);
	if (o->every > 0)
		do
			u.next_frame = ++u.kframe * o->every;
		while (u.next_frame <= r->c0.t);

	u.s.nstage = o->nstage + (o->relax > 0);
	double tcum = 0;
	int done = 1;
	for (int i = 0; i < o->nstage && done; i++) {
		u.s.stage = i;
		dyn_options(u.d)->sigma = o->sig[i];
		/* t1_again in the noisy stages only: in a quench, a four-fold
		 * vertex whose two resolutions both shrink would cycle through
		 * them at its own period for ever (a 324-cell quench never
		 * settled in 8000 time units); the paper's rule lets the
		 * steps decide it */
		dyn_options(u.d)->t1_again = o->sig[i] > 0 ? o->d.t1_again : 0;
		tcum += o->dur[i];
		done = run_to(&u, tcum, stop, r, err, &st);
	}
	dyn_counts_get(u.d, &r->before_relax);
	if (done && o->relax > 0) {
		dyn_options(u.d)->sigma = 0;
		dyn_options(u.d)->t1_again = 0;
		tcum += o->relax;
		u.s.stage = o->nstage;
		done = run_to(&u, tcum, stop, r, err, &st);
	}
	if (st == MESH_OK) {
		status(&u, 0);
		r->last = u.s;
		r->c = u.s.c;
		if (done && o->relax > 0 && m->dg) {
			/* what is left after relaxing is at most exp(-relax/tau) of
			 * the noise: a relaxed sample is passive, with no tension
			 * state */
			free(m->dg);
			m->dg = NULL;
		}
		if (!done) {
			/* a stopped run leaves what continuing it needs */
			char proto[2048];
			anneal_protocol(o, p, proto, sizeof proto);
			if (dyn_state_save(u.d) != MESH_OK || mesh_run_mark(m, "tis-anneal", proto) != MESH_OK ||
			    (o->d.t1_again > 0 && fresh_save(u.d, m) != MESH_OK))
				st = MESH_ENOMEM;
			/* the end state as a row, unless a run that continues
			 * this one goes on from it */
			if (r->why != ANNEAL_END_STOP)
				log_row(&u);
		} else if (mesh_order_spatial(m, MESH_ORDER_ALL) != MESH_OK)
			st = MESH_ENOMEM;
	}
	dyn_free(u.d);
	if (st == MESH_ENOMEM)
		return mesh_error_set(err, 0, st, "out of memory");
	return MESH_OK;
}

int anneal_note(char *buf, size_t n, const anneal_opts *o, const anneal_result *r,
                const char *why)
{
	const dyn_counts *c = &r->c;
#define ADD(...) (len += snprintf(buf + len, n > (size_t)len ? n - len : 0, __VA_ARGS__))
	int len = 0;
	ADD("stages");
	for (int i = 0; i < o->nstage; i++)
		ADD(" %g:%g", o->sig[i], o->dur[i]);
	if (o->relax > 0)
		ADD(", relax %g at sigma=0 (T1s %s, %ld in relax)", o->relax,
		    o->d.t1_length > 0 ? "on" : "off", c->nt1 - r->before_relax.nt1);
	ADD("; tau %g, dt<=%g, dr<=%g, seed %lu; t %.10g, %ld steps, %ld T1s", o->d.tau,
	    o->d.dt_max, o->d.dr_max, o->seed, c->t, c->nstep, c->nt1);
	if (c->nt1_refused)
		ADD(", %ld refused", c->nt1_refused);
	if (o->d.t1_again > 0)
		ADD(" (in noisy stages a junction a T1 made T1'd again only below %g times its length)",
		    o->d.t1_again);
	if (o->d.ou_dt > 0)
		ADD("; noise updated every %g", o->d.ou_dt);
	else
		ADD("; noise updated every step");
	if (c->nsettle > 0)
		ADD("; %ld sigma=0 stages finished by Newton minimization at fixed topology once max "
		    "force and tension <= %g (settle), covering %.10g time units", c->nsettle,
		    o->d.settle, c->t_settled);
	if (o->d.settle_t1)
		ADD("; settling with T1s: %ld jumps to a minimum with T1s to do there",
		    c->nsettle_t1);
	if (o->d.quench == DYN_QUENCH_ADAPTIVE)
		ADD("; adaptive quench: %ld explicit steps landed on a T1, %ld switches to implicit "
		    "steps", c->nevent_expl, c->nswitch);
	if (c->nimpl > 0 || c->nimpl_fail > 0)
		ADD("; %ld implicit steps (local error <= %g, %ld solves, %ld landed on a T1, %ld "
		    "taken explicitly) covering %.10g time units", c->nimpl,
		    o->d.implicit > 0 ? o->d.implicit : DYN_QUENCH_TOL, c->nsolve, c->nevent,
		    c->nimpl_fail, c->t_implicit);
	if (r->continued)
		ADD("; continued from t %.10g", r->c0.t);
	if (why)
		ADD("; %s", why);
#undef ADD
	return len;
}

int anneal_why(char *buf, size_t n, const anneal_result *r, const mesh_error *err,
               const char *log, int log_errno, const char *signal)
{
	if (r->why == ANNEAL_END_FAILED)
		return snprintf(buf, n, "stopped: %s", err->msg);
	if (r->why == ANNEAL_END_IO)
		return snprintf(buf, n, "stopped: %s: write error: %s", log, strerror(log_errno));
	if (r->why == ANNEAL_END_STOP)
		return snprintf(buf, n, "interrupted by %s at step %ld, t = %.10g", signal, r->c.nstep,
		                r->c.t);
	return snprintf(buf, n, "%s", "");
}
