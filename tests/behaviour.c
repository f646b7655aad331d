/* The behaviour classifier on trajectories with known answers: a
 * monotone relaxation, a damped cosine, a sustained cosine (amplitude and
 * period), an asymmetric cycle, l = c (t_c - t)^beta for two exponents
 * (t_c and beta recovered), a settling at a cusp, a noise-driven
 * oscillation, a growing one and a short trace; bad input refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "behaviour.h"
#include "tap.h"

#define PI 3.14159265358979323846

#define N 20001
static double t[N], l[N];

static beh_result run(int n, const char *what)
{
	beh_opts o;
	beh_opts_default(&o);
	o.l0 = 0.62;
	beh_result r;
	mesh_error err;
	if (beh_classify(n, t, l, &o, &r, &err) != MESH_OK)
		diag("%s: %s", what, err.msg);
	return r;
}

static void is_kind(const beh_result *r, beh_kind k, const char *what)
{
	ok(r->kind == k, "%s: %s (got %s)", what, beh_name(k), beh_name(r->kind));
}

/* A standard normal from a fixed LCG and Box-Muller: the test needs
 * reproducible noise, not a good generator. */
static unsigned long long lcg = 12345;
static double unif(void)
{
	lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
	return ((lcg >> 11) + 0.5) / 9007199254740992.0;
}
static double gauss(void) { return sqrt(-2 * log(unif())) * cos(2 * PI * unif()); }

int main(void)
{
	tap_plan(33);
	const double l0 = 0.62, dt = 0.1;
	beh_result r;

	for (int i = 0; i < N; i++) {
		t[i] = i * dt;
		l[i] = l0 + 1e-3 * exp(-t[i] / 20);
	}
	r = run(N, "relaxation");
	is_kind(&r, BEH_STABLE, "monotone exponential relaxation");

	for (int i = 0; i < N; i++)
		l[i] = l0 + 1e-3 * exp(-t[i] / 300) * cos(2 * PI * t[i] / 40);
	r = run(N, "damped");
	is_kind(&r, BEH_DAMPED, "damped cosine");
	/* amplitude decays by exp(-40/300) per period */
	is_near(r.decay, -40.0 / 300, 0.01, "damped cosine: decay per period -T/tau");
	is_near(r.period, 40, 0.01, "damped cosine: period");

	for (int i = 0; i < N; i++)
		l[i] = l0 + 0.05 * sin(2 * PI * t[i] / 35);
	r = run(N, "cycle");
	is_kind(&r, BEH_CYCLE, "sustained cosine");
	is_near(r.amplitude, 0.05, 1e-5, "sustained cosine: amplitude");
	is_near(r.period, 35, 1e-6, "sustained cosine: period");
	/* over 1000 time units, not a whole number of periods: off by at most
	 * A T / (pi 1000) */
	is_near(r.l_mean, l0, 0.05 * 35 / (PI * 1000), "sustained cosine: mean length l0");

	/* the cycle tolerance (0.01 in log amplitude per period) from both
	 * sides: a slow decay or growth within it is a cycle, beyond it
	 * damped or undecided (still growing) */
	const double rho[4] = { -0.008, 0.008, -0.012, 0.012 };
	const beh_kind want[4] = { BEH_CYCLE, BEH_CYCLE, BEH_DAMPED, BEH_UNDECIDED };
	double worst = 0;
	for (int c = 0; c < 4; c++) {
		for (int i = 0; i < N; i++)
			l[i] = l0 + 0.01 * exp(rho[c] * t[i] / 40) * sin(2 * PI * t[i] / 40);
		r = run(N, "cycle tolerance");
		char what[80];
		snprintf(what, sizeof what, "amplitude growth %+.3f per period (tolerance 0.01)", rho[c]);
		is_kind(&r, want[c], what);
		worst = fmax(worst, fabs(r.decay - rho[c]));
	}
	ok(worst < 5e-4, "and the decay per period measured within 5e-4 (worst %.2g)", worst);
	{
		/* a tolerance given: the same trace at 0.012 is a cycle under 0.02 */
		beh_opts o;
		beh_opts_default(&o);
		o.l0 = l0;
		o.cycle_tol = 0.02;
		mesh_error err;
		beh_classify(N, t, l, &o, &r, &err);
		is_kind(&r, BEH_CYCLE, "growth 0.012 per period with cycle_tol 0.02");
	}

	/* a nonlinear cycle: asymmetric about l0, with a harmonic */
	for (int i = 0; i < N; i++) {
		double ph = 2 * PI * t[i] / 50;
		l[i] = l0 + 0.1 * sin(ph) + 0.04 * cos(2 * ph) + 0.02;
	}
	r = run(N, "asymmetric");
	is_kind(&r, BEH_CYCLE, "asymmetric cycle with a harmonic");
	is_near(r.period, 50, 1e-6, "asymmetric cycle: period");

	/* collapse: l = c (t_c - t)^beta, the trace stopping short of t_c */
	const double tc = 500, betas[2] = { 0.5, 0.7 };
	for (int b = 0; b < 2; b++) {
		int n = 0;
		for (double tt = 0; tt < tc - 1e-4; tt += 0.5, n++) {
			t[n] = tt;
			l[n] = 0.62 * pow((tc - tt) / tc, betas[b]);
		}
		/* the last row: where the run stopped, 1e-4 before t_c */
		t[n] = tc - 1e-4;
		l[n] = 0.62 * pow(1e-4 / tc, betas[b]);
		n++;
		r = run(n, "collapse");
		is_kind(&r, BEH_COLLAPSE, betas[b] == 0.5 ? "l ~ (t_c - t)^0.5" : "l ~ (t_c - t)^0.7");
		is_near(r.beta, betas[b], 1e-6, "collapse: exponent beta");
		is_near(r.t_c, tc, 1e-6, "collapse: t_c");
	}

	/* settling at a cusp: l goes from l0 to 0.35 and stays there */
	for (int i = 0; i < N; i++) {
		t[i] = i * dt;
		l[i] = 0.35 + (l0 - 0.35) * exp(-t[i] / 30);
	}
	r = run(N, "cusp");
	is_kind(&r, BEH_CUSP, "condensation away from l0");
	is_near(r.l_mean, 0.35, 1e-6, "cusp: mean length at the cusp");
	/* the cusp rule's |l_end - l0| >= 0.05 l0 from both sides: settling
	 * 6 % from l0 is a cusp, 4 % is not (at rest off l0: stable) */
	for (int side = 0; side < 2; side++) {
		double lend = l0 * (side ? 0.96 : 0.94);
		for (int i = 0; i < N; i++)
			l[i] = lend + (l0 - lend) * exp(-t[i] / 30);
		r = run(N, "cusp edge");
		is_kind(&r, side ? BEH_STABLE : BEH_CUSP, side ? "settling 4 % from l0" : "settling 6 % from l0");
	}

	/* at rest near l0, not at it (a floppy tissue's zero modes) */
	for (int i = 0; i < N; i++)
		l[i] = l0 - 1e-3 * (1 - exp(-t[i] / 50));
	r = run(N, "settled");
	is_kind(&r, BEH_STABLE, "settling 1e-3 below l0");

	/* noise-driven oscillation: an OU-driven damped oscillator */
	double x = 0, v = 0, w = 2 * PI / 40, g = 0.05;
	for (int i = 0; i < N; i++) {
		l[i] = l0 + x;
		for (int k = 0; k < 10; k++) {
			double h = dt / 10;
			v += h * (-w * w * x - g * v) + sqrt(h) * 1e-3 * gauss();
			x += h * v;
		}
	}
	r = run(N, "quasicycle");
	is_kind(&r, BEH_QUASICYCLE, "noise-sustained oscillation");
	ok(r.irregularity > 0.1, "quasicycle: irregular (%.3g)", r.irregularity);

	/* a growing oscillation that has not saturated: too short to tell */
	for (int i = 0; i < N; i++)
		l[i] = l0 + 1e-4 * exp(t[i] / 500) * sin(2 * PI * t[i] / 40);
	r = run(N, "growing");
	is_kind(&r, BEH_UNDECIDED, "growing oscillation");

	r = run(5, "short");
	is_kind(&r, BEH_UNDECIDED, "five rows");

	/* bad input */
	beh_opts o;
	beh_opts_default(&o);
	mesh_error err;
	t[3] = t[2];
	ok(beh_classify(10, t, l, &o, &r, &err) == MESH_EINVAL && err.line == 4,
	   "time that does not increase: refused at row 4");
	t[3] = 0.3;
	l[2] = -1;
	ok(beh_classify(10, t, l, &o, &r, &err) == MESH_EINVAL, "negative length refused");
	return tap_done();
}
