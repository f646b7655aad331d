/* cli_memory.c - the memory a job may take. */
#include "cli.h"

#include <math.h>
#include <sys/resource.h>
#include <unistd.h>

/* Memory the system can give now (MemAvailable), or all of it if that is
 * unknown; 0 if neither is. */
static double available_bytes(void)
{
	FILE *f = fopen("/proc/meminfo", "r");
	if (f) {
		char line[256];
		double kb = 0;
		while (fgets(line, sizeof line, f))
			if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1)
				break;
		fclose(f);
		if (kb > 0)
			return kb * 1024;
	}
	long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
	return pages > 0 && size > 0 ? (double)pages * size : 0;
}

/* The smaller of that and the address-space limit (ulimit -v). */
static double usable_bytes(void)
{
	double avail = available_bytes();
	struct rlimit rl;
	if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
	    (avail == 0 || (double)rl.rlim_cur < avail))
		avail = (double)rl.rlim_cur;
	return avail;
}

double cli_max_memory(const char *arg)
{
	if (arg)
		return cli_size("--max-memory", arg);
	double avail = usable_bytes();
	return avail > 0 ? avail : INFINITY;
}

void cli_fits(int st, const mesh_error *err, int given)
{
	if (st == MESH_ETOOBIG)
		cli_die(EXIT_INPUT, "%s (%s)", err->msg,
		        given ? "--max-memory" : "the memory available now; see --max-memory");
	if (st != MESH_OK)
		cli_die(EXIT_INPUT, "%s", err->msg);
}

void cli_size_check(const char *what, double mem, double out)
{
	double avail = usable_bytes();
	if (avail > 0 && mem > avail)
		cli_die(EXIT_INPUT, "%s would need about %.1f GB of memory, %.1f GB available: "
		        "refused", what, mem / 1e9, avail / 1e9);
	if (mem > 1e9 || out > 1e9)
		cli_warn("%s: about %.1f GB of memory and %.1f GB of output", what, mem / 1e9,
		         out / 1e9);
}
