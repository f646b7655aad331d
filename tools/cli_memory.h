/* cli_memory.h - hostile sizes: a job too large for the machine is
 * refused with one line before it starts. */
#ifndef TIS_CLI_MEMORY_H
#define TIS_CLI_MEMORY_H

#include "mesh.h"

/* A job that would need mem bytes of memory (an estimate the caller
 * measured, bench/RESULTS.md) and write out bytes is refused (exit 1, one
 * line) if mem is more than the system has available now, and announced
 * on stderr (what it will cost) if either is above 1 GB.  what names the
 * job ("tis-hex 10000 1000: 1e7 cells"). */
void cli_size_check(const char *what, double mem, double out);
/* The memory limit of a program's dense work (--max-memory): arg, a
 * size (cli_size), if it is not NULL; else what the system has
 * available now, as cli_size_check takes it (INFINITY if unknown). */
double cli_max_memory(const char *arg);
/* A job refused before it started (st from the library's check, such as
 * stab_fits): exit 1 with its message, which for MESH_ETOOBIG also says
 * where the limit came from (given: --max-memory); nothing if st is
 * MESH_OK. */
void cli_fits(int st, const mesh_error *err, int given);

#endif
