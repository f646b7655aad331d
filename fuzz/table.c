/* fuzz/table.c - libFuzzer harness for the TSV reader (libmesh/core/table.c)
 * as tis-fit uses it: the program
 * itself (tools/tis-fit.c and tools/cli*.c compiled into this file) runs on
 * every input in-process.  Its exit() (cli_die on bad input, cli_finish)
 * returns here by longjmp, stdout and stderr go to /dev/null, and the
 * input is what fopen of the program's argument opens.  The first byte
 * picks the options (plain fit, --cusps, --summary, --branch all,
 * --degree 1 --window 0).  What the program allocates (malloc, realloc,
 * getline in these files) is tracked and freed after it exits, as
 * exit would, and so are its table reader, provenance mesh, curve and
 * summary groups (file scope in tis-fit.c); what else libmesh allocates for it and does not get
 * back is leaked (run with -detect_leaks=0). */
#include <errno.h>
#include <getopt.h>
#include <gsl/gsl_errno.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

static jmp_buf fuzz_back;
static const uint8_t *fuzz_data;
static size_t fuzz_size;

/* the program's live allocations */
static void **live;
static size_t nlive, caplive;

static void track(void *p)
{
	if (p == NULL)
		return;
	if (nlive == caplive) {
		caplive = caplive ? 2 * caplive : 256;
		live = realloc(live, caplive * sizeof *live);
		if (live == NULL)
			abort();
	}
	live[nlive++] = p;
}

static void untrack(void *p)
{
	for (size_t i = nlive; i-- > 0;)
		if (live[i] == p) {
			live[i] = live[--nlive];
			return;
		}
}

static void *fuzz_malloc(size_t n)
{
	void *p = malloc(n);
	track(p);
	return p;
}

__attribute__((unused)) static void *fuzz_calloc(size_t n, size_t k)
{
	void *p = calloc(n, k);
	track(p);
	return p;
}

static void *fuzz_realloc(void *q, size_t n)
{
	void *p = realloc(q, n);
	if (p != NULL || n == 0) {
		untrack(q);
		track(p);
	}
	return p;
}

static void fuzz_free(void *p)
{
	untrack(p);
	free(p);
}

__attribute__((unused)) static ssize_t fuzz_getline(char **buf, size_t *cap, FILE *f)
{
	char *old = *buf;
	ssize_t n = getline(buf, cap, f);
	if (*buf != old) {
		untrack(old);
		track(*buf);
	}
	return n;
}

static void free_live(void)
{
	while (nlive > 0)
		free(live[--nlive]);
}

_Noreturn static void fuzz_exit(int status)
{
	longjmp(fuzz_back, status + 1);
}

/* the input stream, closed after the run if the program exits without
 * closing it (an open FILE is reachable, so no leak check sees it) */
static FILE *fuzz_in;

static FILE *fuzz_fopen(const char *path, const char *mode)
{
	if (strcmp(path, "fuzz-input") == 0)
		return fuzz_in = fmemopen((void *)fuzz_data, fuzz_size ? fuzz_size : 1, mode);
	return fopen(path, mode);
}

static int fuzz_fclose(FILE *f)
{
	if (f == stdout || f == stderr)
		return fflush(f);
	if (f == fuzz_in)
		fuzz_in = NULL;
	return fclose(f);
}

#define exit fuzz_exit
#define malloc fuzz_malloc
#define calloc fuzz_calloc
#define realloc fuzz_realloc
#define free fuzz_free
#define getline fuzz_getline
#define fopen fuzz_fopen
#define fclose fuzz_fclose
#define main tis_fit_main
#include "../tools/cli.c"
#include "../tools/cli_opt.c"
#include "../tools/cli_threads.c"
#include "../tools/cli_mesh.c"
#include "../tools/cli_table.c"
#include "../tools/cli_memory.c"
#include "../tools/cli_signal.c"
#include "../tools/cli_progress.c"
#include "../tools/tis-fit.c"
#undef main
#undef malloc
#undef calloc
#undef realloc
#undef free

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	if (!freopen("/dev/null", "w", stdout))
		abort();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static char *const modes[][6] = {
		{ "tis-fit", "fuzz-input", NULL },
		{ "tis-fit", "--cusps", "fuzz-input", NULL },
		{ "tis-fit", "--summary", "fuzz-input", NULL },
		{ "tis-fit", "--branch", "all", "fuzz-input", NULL },
		{ "tis-fit", "--degree", "1", "--window", "0", "fuzz-input" },
	};
	if (size == 0)
		return 0;
	int mode = data[0] % 5;
	fuzz_data = data + 1;
	fuzz_size = size - 1;
	int argc = 0;
	while (argc < 6 && modes[mode][argc])
		argc++;
	char *argv[8];
	memcpy(argv, modes[mode], (size_t)argc * sizeof *argv);
	argv[argc] = NULL;
	cli_stop = 0;
	optind = 0;   /* glibc: a full re-initialization of getopt */
	if (setjmp(fuzz_back) == 0)
		tis_fit_main(argc, argv);
	free_live();
	table_reader_free(rd);
	rd = NULL;
	mesh_free(prov);
	prov = NULL;
	fit_curve_free(&curve);
	fit_groups_free(&groups);
	if (fuzz_in) {
		fclose(fuzz_in);
		fuzz_in = NULL;
	}
	clearerr(stdout);
	return 0;
}
