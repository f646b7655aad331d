/* noise.h - Ornstein-Uhlenbeck junction-tension noise on a GSL RNG.
 *
 *   d(dg)/dt = -dg/tau + sqrt(2 sigma^2/tau) xi(t)
 *
 * has long-time variance sigma^2 and autocorrelation exp(-|t|/tau).  It is
 * stepped exactly, for any dt:
 *
 *   dg <- dg e^{-dt/tau} + sigma sqrt(1 - e^{-2 dt/tau}) N(0,1)
 *
 * The generator is GSL's taus2 (L'Ecuyer's maximally equidistributed
 * combined Tausworthe generator, period 2^88) with GSL's ziggurat
 * Gaussians: the same seed gives the same numbers on every machine.  With sigma = 0 no random
 * numbers are drawn (the tensions only decay), so a sigma = 0 stage does
 * not shift the stream of a later noisy one.
 */
#ifndef TIS_NOISE_H
#define TIS_NOISE_H

#include <stddef.h>

typedef struct ou_noise ou_noise;

/* A generator seeded with seed; NULL if out of memory. */
ou_noise *ou_alloc(unsigned long seed);
void ou_free(ou_noise *n);

/* The generator's state as text (a run that stops saves it in the mesh,
 * so that continuing gives the numbers an uninterrupted run would have
 * drawn): "taus2 " and the state's bytes in hex, into buf of size n.
 * MESH_OK, or MESH_EDOM if n is too small. */
int ou_state_get(const ou_noise *g, char *buf, size_t n);
/* Restore a state written by ou_state_get.  MESH_OK, or MESH_EINVAL if the
 * text is not such a state. */
int ou_state_set(ou_noise *g, const char *text);
#define OU_STATE_LEN 128   /* enough for ou_state_get */

/* One standard normal number. */
double ou_gauss(ou_noise *n);

/* Advance the n values x[i] (only those with mask[i] != 0 when mask is not
 * NULL) by one exact OU step of length dt >= 0 with time constant tau > 0.
 * Values that decay below 1e-150 in magnitude without noise become exactly
 * 0, so a quenched tissue does not crawl through subnormal arithmetic.
 * g may be NULL when sigma = 0. */
void ou_step(ou_noise *g, double *x, int n, const unsigned char *mask,
             double dt, double tau, double sigma);

#endif
