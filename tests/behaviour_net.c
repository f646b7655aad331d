/* The network classifier (beh_network) on trajectories with known
 * answers: tensions that die out (stable), a sustained oscillation of W
 * (its period and amplitude recovered), one that dies out, f6 rising
 * (ordering) and falling under a T1 storm (collapse, its T1 rate), an
 * irregular active trace (undecided), a short trace; bad input refused. */
#include <math.h>
#include <stdlib.h>

#include "behaviour.h"
#include "tap.h"

#define PI 3.14159265358979323846
#define N 2001
static double t[N], f6[N], W[N], nt1[N], sd[N];

static beh_net_result run(int n)
{
	beh_net_opts o;
	beh_net_opts_default(&o);
	beh_net_result r;
	mesh_error err;
	if (beh_network(n, t, f6, W, nt1, sd, &o, &r, &err) != MESH_OK)
		diag("beh_network: %s", err.msg);
	return r;
}

static void is_kind(const beh_net_result *r, beh_net_kind k, const char *what)
{
	ok(r->kind == k, "%s: %s (got %s)", what, beh_net_name(k), beh_net_name(r->kind));
}

/* A quiet baseline: f6 constant, W at rest, no T1s, tensions of spread s. */
static void base(double s)
{
	for (int i = 0; i < N; i++) {
		t[i] = 0.5 * i;
		f6[i] = 0.9;
		W[i] = 2.9;
		nt1[i] = 0;
		sd[i] = s;
	}
}

int main(void)
{
	tap_plan(11);
	beh_net_result r;

	base(0);
	for (int i = 0; i < N; i++)
		sd[i] = 1e-4 * exp(-t[i] / 50);
	r = run(N);
	is_kind(&r, BEH_NET_STABLE, "tension spread decaying");

	base(0.05);
	for (int i = 0; i < N; i++)
		W[i] = 2.9 + 0.3 * sin(2 * PI * t[i] / 37);
	r = run(N);
	is_kind(&r, BEH_NET_OSCILLATION, "sustained oscillation of W");
	ok(fabs(r.period - 37) < 0.5 && fabs(r.amplitude - 0.3) < 0.01,
	   "its period %.3f (37) and amplitude %.4f (0.3)", r.period, r.amplitude);

	base(0.05);
	for (int i = 0; i < N; i++) {
		W[i] = 2.9 + 0.3 * exp(-t[i] / 100) * sin(2 * PI * t[i] / 37);
		sd[i] = 0.05 * exp(-t[i] / 100);
	}
	r = run(N);
	is_kind(&r, BEH_NET_STABLE, "oscillation dying out with its tensions");

	base(0.05);
	for (int i = 0; i < N; i++) {
		f6[i] = 0.52 + 0.3 * (1 - exp(-t[i] / 100)) + 0.01 * sin(t[i]);
		nt1[i] = 3000 * (1 - exp(-t[i] / 100));
	}
	r = run(N);
	is_kind(&r, BEH_NET_ORDERING, "f6 rising by T1s");

	base(0.5);
	for (int i = 0; i < N; i++) {
		f6[i] = 0.9 - 0.5 * (1 - exp(-t[i] / 20));
		nt1[i] = 4000 * t[i];
	}
	r = run(N);
	is_kind(&r, BEH_NET_COLLAPSE, "f6 falling under a T1 storm");
	ok(fabs(r.t1_rate - 4000) < 1e-6, "its T1 rate over the tail (%g, 4000)", r.t1_rate);

	/* active, irregular, no period: W a sum of incommensurate waves with
	 * a growing drift, tensions sustained */
	base(0.3);
	for (int i = 0; i < N; i++)
		W[i] = 2.9 + 0.002 * t[i] + 0.01 * sin(t[i] * 2.1);
	r = run(N);
	is_kind(&r, BEH_NET_UNDECIDED, "active, drifting, without oscillation");

	r = run(5);
	is_kind(&r, BEH_NET_UNDECIDED, "five rows");

	beh_net_opts o;
	beh_net_opts_default(&o);
	mesh_error err;
	base(0);
	t[3] = t[2];
	ok(beh_network(N, t, f6, W, nt1, sd, &o, &r, &err) == MESH_EINVAL && err.line == 4,
	   "time not increasing refused at its row (%s)", err.msg);
	base(0);
	W[7] = NAN;
	ok(beh_network(N, t, f6, W, nt1, sd, &o, &r, &err) == MESH_EINVAL && err.line == 8,
	   "a non-finite W refused at its row");
	return tap_done();
}
