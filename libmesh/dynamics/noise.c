/* noise.c - exact Ornstein-Uhlenbeck steps on GSL's taus2. */
#include "noise.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "mesh.h"

struct ou_noise {
	gsl_rng *rng;
	double dt, tau, a, b;   /* last step's decay and noise factors */
};

ou_noise *ou_alloc(unsigned long seed)
{
	ou_noise *g = malloc(sizeof *g);
	if (g == NULL)
		return NULL;
	/* taus2 rather than MT19937: 7.4 ns per ziggurat Gaussian against
	 * 12.1 (bench/RESULTS.md), and a noisy step draws one per junction */
	g->rng = gsl_rng_alloc(gsl_rng_taus2);
	if (g->rng == NULL) {
		free(g);
		return NULL;
	}
	gsl_rng_set(g->rng, seed);
	g->dt = g->tau = -1;
	g->a = g->b = 0;
	return g;
}

void ou_free(ou_noise *g)
{
	if (g == NULL)
		return;
	gsl_rng_free(g->rng);
	free(g);
}

int ou_state_get(const ou_noise *g, char *buf, size_t n)
{
	size_t sz = gsl_rng_size(g->rng);
	const unsigned char *st = gsl_rng_state(g->rng);
	const char *name = gsl_rng_name(g->rng);
	if (n < strlen(name) + 2 + 2 * sz)
		return MESH_EDOM;
	size_t k = (size_t)sprintf(buf, "%s ", name);
	for (size_t i = 0; i < sz; i++)
		k += (size_t)sprintf(buf + k, "%02x", st[i]);
	return MESH_OK;
}

int ou_state_set(ou_noise *g, const char *text)
{
	const char *name = gsl_rng_name(g->rng);
	size_t nl = strlen(name), sz = gsl_rng_size(g->rng);
	if (strncmp(text, name, nl) != 0 || text[nl] != ' ' ||
	    strlen(text + nl + 1) != 2 * sz)
		return MESH_EINVAL;
	unsigned char *st = gsl_rng_state(g->rng), tmp[64];
	if (sz > sizeof tmp)
		return MESH_EINVAL;
	for (size_t i = 0; i < sz; i++) {
		unsigned v;
		const char *h = text + nl + 1 + 2 * i;
		if (!isxdigit((unsigned char)h[0]) || !isxdigit((unsigned char)h[1]) ||
		    sscanf(h, "%2x", &v) != 1)
			return MESH_EINVAL;
		tmp[i] = (unsigned char)v;
	}
	memcpy(st, tmp, sz);
	return MESH_OK;
}

double ou_gauss(ou_noise *g)
{
	return gsl_ran_gaussian_ziggurat(g->rng, 1.0);
}

void ou_step(ou_noise *g, double *x, int n, const unsigned char *mask,
             double dt, double tau, double sigma)
{
	if (g == NULL) {
		/* no generator: only decay is possible */
		double a = exp(-dt / tau);
		for (int i = 0; i < n; i++)
			if (mask == NULL || mask[i]) {
				double v = x[i] * a;
				x[i] = fabs(v) < 1e-150 ? 0.0 : v;
			}
		return;
	}
	/* Most steps have dt = dt_max: reuse the two transcendental factors. */
	if (dt != g->dt || tau != g->tau) {
		g->dt = dt;
		g->tau = tau;
		g->a = exp(-dt / tau);
		g->b = sqrt(-expm1(-2 * dt / tau));   /* accurate for small dt */
	}
	double a = g->a, b = sigma * g->b;
	if (sigma == 0) {
		for (int i = 0; i < n; i++) {
			if (mask && !mask[i])
				continue;
			double v = x[i] * a;
			x[i] = fabs(v) < 1e-150 ? 0.0 : v;
		}
		return;
	}
	for (int i = 0; i < n; i++)
		if (mask == NULL || mask[i])
			x[i] = x[i] * a + b * gsl_ran_gaussian_ziggurat(g->rng, 1.0);
}
