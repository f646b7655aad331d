/* cli_opt.h - option values: numbers, sizes, lists, vertex pairs, the
 * junction choices and the model parameters every program takes the same
 * way.  A value that is not what its option takes is a usage error naming
 * the option (exit 2). */
#ifndef TIS_CLI_OPT_H
#define TIS_CLI_OPT_H

#include "energy.h"
#include "mesh.h"
#include "select.h"

/* Option values: the whole argument must be a finite number (or an integer
 * within [lo, hi]); otherwise a usage error naming the option. */
double cli_double(const char *opt, const char *arg);
double cli_double_range(const char *opt, const char *arg, double lo, double hi);
long cli_long(const char *opt, const char *arg, long lo, long hi);
/* Model parameter name given by option opt: a finite number in the range
 * every source of it shares (range.h); otherwise a usage error. */
double cli_param(const char *opt, const char *arg, const char *name);
/* --box LX LY: two numbers in range_box's range. */
void cli_box(const char *ax, const char *ay, double *lx, double *ly);

/* A size in bytes: a number > 0, alone or with one of the suffixes k, M,
 * G, T (10^3, 10^6, 10^9, 10^12: "8G", "1.5G", "512M"); otherwise a
 * usage error naming the option. */
double cli_size(const char *opt, const char *arg);

/* A list option: "v1,v2,..." or a range "lo:hi:n" (n points, both ends
 * included), each value finite; malloc'd, *n values.  Usage error
 * otherwise. */
double *cli_double_list(const char *opt, const char *arg, int *n);

/* cli_double_list whose every value is > lo (strict) or >= lo; a usage
 * error "OPT: every value must be > LO (got V)" otherwise. */
double *cli_double_list_above(const char *opt, const char *arg, int *n, double lo,
                              int strict);

/* "k1,k2,...": integers in [lo, hi] (cli_long each); malloc'd, *n of them.
 * Usage error otherwise. */
int *cli_int_list(const char *opt, const char *arg, long lo, long hi, int *n);

/* The two vertex ids of an option like --junction A B inside a getopt_long
 * loop: A is optarg, B the next argument (optind moves past it). */
void cli_vertex_pair(const char *opt, int argc, char *const argv[], long *a, long *b);

/* A junction option (select.h) inside a getopt_long loop, by its long
 * name: "junction" A B (JSEL_PAIR; B is the next argument), "index" K,
 * "random" K, "list" FILE, "regular" K, any other name every junction (JSEL_ALL:
 * --all, --network).  A second choice is a usage error with the message
 * choose, unless again is set and it is the same kind (the last value
 * counts). */
void cli_jsel(jsel *js, const char *name, int again, const char *choose, int argc,
              char *const argv[]);

/* The junctions js chooses of m (junction_select: malloc'd, *n of them);
 * exit 1 with the reason if it cannot. */
int *cli_junctions(const mesh *m, const jsel *js, int *n);

/* Model parameters given on the command line (--p0, --ka), which
 * override the mesh's.  cli_model_option takes one: name "p0" or "ka",
 * arg its value (cli_param: the range every source of it shares).
 * cli_model gives the model of m with them; cli_model_set writes them
 * into m's params (exit 1 if out of memory), so that the mesh written
 * carries them. */
typedef struct {
	int has_p0, has_ka;
	double p0, ka;
} cli_model_opts;
void cli_model_option(cli_model_opts *mo, const char *name, const char *arg);
model cli_model(const mesh *m, const cli_model_opts *mo);
void cli_model_set(mesh *m, const cli_model_opts *mo);

/* A program's options as a table that cli_parse reads: each entry an
 * option by its long name, what kind of argument it takes and where its
 * value goes, so that parse() is the table and the checks between
 * options.  Messages are those of the functions above, naming the option
 * as --name; -h/--help (cli_help) and --version (cli_version) come with
 * every table, and the short options are -h and an entry's key.  At most
 * 96 entries. */
typedef enum {
	CLI_FLAG,       /* no argument: *(int *)to = val */
	CLI_DOUBLE,     /* a number in [lo, hi] (cli_double_range): *(double *)to */
	CLI_INVERSE,    /* the same, its reciprocal: *(double *)to (a rate for
	                   a time) */
	CLI_INT,        /* an integer in [lo, hi] (cli_long): *(int *)to */
	CLI_LONG,       /* the same: *(long *)to */
	CLI_ULONG,      /* the same: *(unsigned long *)to (lo >= 0) */
	CLI_STRING,     /* the argument itself: *(const char **)to */
	CLI_JUNCTIONS,  /* a junction choice (cli_jsel with again val and
	                   choose msg, if NULL "choose one of --a, --b, ..."
	                   naming the table's junction options): *(jsel *)to */
	CLI_ALL,        /* the same without an argument: every junction
	                   (--all, --network) */
	CLI_MODEL,      /* "p0" or "ka" (cli_model_option): *(cli_model_opts *)to */
	CLI_PARSE,      /* parse(to, argument); nonzero: a usage error, the
	                   message msg with the argument for its one %s */
	CLI_CALL        /* no argument: parse(to, NULL), in its place among
	                   the options (a preset that later ones override) */
} cli_optkind;

typedef struct {
	const char *name;   /* the long name, without the dashes; NULL ends a table */
	cli_optkind kind;
	void *to;
	double lo, hi;      /* the range of a number */
	int val;            /* CLI_FLAG's value, CLI_JUNCTIONS' and CLI_ALL's again */
	const char *msg;    /* CLI_PARSE's usage error (where parse can fail),
	                       CLI_JUNCTIONS' and CLI_ALL's choose */
	int (*parse)(void *to, const char *arg);
	unsigned group;     /* bits the program chooses, for cli_opt_first */
	int key;            /* its short option as well (-q), 0: none */
	int seen;           /* set by cli_parse: the option's first place among
	                       those given (1, 2, ...), 0 if not given */
} cli_optdef;

/* Parse the options of argv by defs (getopt_long: long names and their
 * unambiguous prefixes, "--name=value" too) in order, each value where its
 * entry says; an unknown option or a missing argument is cli_bad_option's
 * usage error, -h/--help prints help.  Returns the index in argv of the
 * first operand (optind). */
int cli_parse(int argc, char **argv, cli_optdef *defs, const char *help);
/* The long name of the option given first among those of defs whose
 * group shares a bit with group, NULL if none was given. */
const char *cli_opt_first(const cli_optdef *defs, unsigned group);
/* Unless one of the junction options of defs (CLI_JUNCTIONS, CLI_ALL) was
 * given, a usage error "choose junctions with --a, --b or --c" naming
 * them in the table's order. */
void cli_opt_junctions(const cli_optdef *defs);
/* A usage error "--NAME is for --WITH" if option name of defs was given
 * without option with. */
void cli_opt_only_with(const cli_optdef *defs, const char *name, const char *with);
/* The input file operand from argv[first] on: NULL (stdin) if none, a
 * usage error if more than one. */
const char *cli_opt_input(int argc, char **argv, int first);

#endif
