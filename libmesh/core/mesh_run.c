/* mesh_run.c - what a mesh says beyond its tissue: parameters, run state
 * and the continuation mark, history lines. */
#include "mesh.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_int.h"
#include "range.h"

/* ---- parameters and history ---- */

int mesh_param_get(const mesh *m, const char *name, double *v)
{
	for (int i = 0; i < m->nparam; i++)
		if (strcmp(m->param[i].name, name) == 0) {
			*v = m->param[i].value;
			return 1;
		}
	return 0;
}

int mesh_param_set(mesh *m, const char *name, double v)
{
	if (strlen(name) >= sizeof m->param[0].name)
		return MESH_EDOM;
	for (int i = 0; i < m->nparam; i++)
		if (strcmp(m->param[i].name, name) == 0) {
			m->param[i].value = v;
			return MESH_OK;
		}
	mesh_param *p = realloc(m->param, (m->nparam + 1) * sizeof *p);
	if (p == NULL)
		return MESH_ENOMEM;
	m->param = p;
	strcpy(p[m->nparam].name, name);
	p[m->nparam].value = v;
	m->nparam++;
	return MESH_OK;
}


const char *mesh_state_get(const mesh *m, const char *name)
{
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0)
			return m->state[i].text;
	return NULL;
}

/* Text as the reader gives it back: line breaks become blanks and leading
 * blanks go (the reader skips the blanks after a keyword), so that what is
 * written reads back to the same text. */
static void line_text(char *s)
{
	for (char *p = s; *p; p++)
		if (*p == '\n' || *p == '\r')
			*p = ' ';
	size_t k = strspn(s, " \t");
	if (k > 0)
		memmove(s, s + k, strlen(s + k) + 1);
}

int mesh_state_set(mesh *m, const char *name, const char *text)
{
	if (!mesh_name_ok(name))
		return MESH_EDOM;
	char *t = strdup(text);
	if (t == NULL)
		return MESH_ENOMEM;
	line_text(t);
	if (*t == '\0') {
		free(t);
		return MESH_EDOM;
	}
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0) {
			free(m->state[i].text);
			m->state[i].text = t;
			return MESH_OK;
		}
	mesh_state *s = realloc(m->state, (m->nstate + 1) * sizeof *s);
	if (s == NULL) {
		free(t);
		return MESH_ENOMEM;
	}
	m->state = s;
	strcpy(s[m->nstate].name, name);
	s[m->nstate].text = t;
	m->nstate++;
	return MESH_OK;
}

void mesh_state_del(mesh *m, const char *name)
{
	for (int i = 0; i < m->nstate; i++)
		if (strcmp(m->state[i].name, name) == 0) {
			free(m->state[i].text);
			memmove(&m->state[i], &m->state[i + 1], (size_t)(m->nstate - i - 1) * sizeof *m->state);
			m->nstate--;
			return;
		}
}

void mesh_state_clear(mesh *m)
{
	for (int i = 0; i < m->nstate; i++)
		free(m->state[i].text);
	free(m->state);
	m->state = NULL;
	m->nstate = 0;
}

void mesh_run_key(char *key, size_t n, const char *name, const char *text)
{
	size_t len = strlen(key);
	if (len < n)
		snprintf(key + len, n - len, "%s%s %s", len ? " " : "", name, text);
}

void mesh_run_key_num(char *key, size_t n, const char *name, double v)
{
	char t[32];
	/* the shortest text that reads back to v: exact, and what a person
	 * reading the refusal gave */
	for (int prec = 1; prec <= 17; prec++) {
		snprintf(t, sizeof t, "%.*g", prec, v);
		if (strtod(t, NULL) == v)
			break;
	}
	mesh_run_key(key, n, name, t);
}

int mesh_run_mark(mesh *m, const char *program, const char *key)
{
	if (strpbrk(key, "\n\r") || strpbrk(program, " \t\n\r") || !*program || !*key)
		return MESH_EDOM;
	size_t n = strlen(program) + strlen(key) + 2;
	char *t = malloc(n);
	if (t == NULL)
		return MESH_ENOMEM;
	snprintf(t, n, "%s %s", program, key);
	int st = mesh_state_set(m, "run", t);
	free(t);
	return st;
}

/* The value of pair NAME in a key ("name value ..."): its start and
 * length in *len, or NULL. */
static const char *key_value(const char *key, const char *name, size_t nlen, size_t *len)
{
	for (const char *p = key; *p;) {
		p += strspn(p, " ");
		size_t a = strcspn(p, " ");
		const char *v = p + a + strspn(p + a, " ");
		size_t b = strcspn(v, " ");
		if (a == nlen && strncmp(p, name, nlen) == 0) {
			*len = b;
			return v;
		}
		p = v + b;
	}
	return NULL;
}

/* Append to buf (size n) what differs between the stopped run's key a
 * and the new one b ("name va, not vb"); with only_new the pairs of b
 * that a lacks ("name unset, not vb"; a and b swapped). */
static void key_diff(char *buf, size_t n, const char *a, const char *b, int only_new)
{
	for (const char *p = a; *p;) {
		p += strspn(p, " ");
		size_t na = strcspn(p, " ");
		const char *v = p + na + strspn(p + na, " ");
		size_t nv = strcspn(v, " "), nw = 0;
		const char *w = key_value(b, p, na, &nw);
		size_t len = strlen(buf);
		int differs = only_new ? w == NULL : w == NULL || nw != nv || strncmp(v, w, nv) != 0;
		if (na && differs && len + 1 < n) {
			if (only_new)
				snprintf(buf + len, n - len, "%s%.*s unset, not %.*s", len ? "; " : "",
				         (int)na, p, (int)nv, v);
			else
				snprintf(buf + len, n - len, "%s%.*s %.*s, not %.*s", len ? "; " : "",
				         (int)na, p, (int)nv, v, w ? (int)nw : 5, w ? w : "unset");
		}
		p = v + nv;
	}
}

int mesh_run_check(const mesh *m, const char *program, const char *key, int *continued,
                   mesh_error *err)
{
	const char *mark = mesh_state_get(m, "run");
	*continued = 0;
	if (mark == NULL)
		return MESH_OK;
	size_t np = strcspn(mark, " ");
	const char *was = mark + np + strspn(mark + np, " ");
	if (np != strlen(program) || strncmp(mark, program, np) != 0)
		return mesh_error_set(err, 0, MESH_EINVAL, "the mesh holds the state of a stopped %.*s "
		                      "run: continue it with %.*s, or remove its state lines to start "
		                      "anew", (int)np, mark, (int)np, mark);
	if (strcmp(was, key) != 0) {
		char d[160] = "";
		key_diff(d, sizeof d, was, key, 0);
		key_diff(d, sizeof d, key, was, 1);
		return mesh_error_set(err, 0, MESH_EINVAL, "the mesh holds the state of a %s run "
		                      "stopped with other options (%s): give the same options to "
		                      "continue it", program, d[0] ? d : was);
	}
	*continued = 1;
	return MESH_OK;
}

int mesh_history_add(mesh *m, const char *text)
{
	char **h = realloc(m->hist, (m->nhist + 1) * sizeof *h);
	if (h == NULL)
		return MESH_ENOMEM;
	m->hist = h;
	char *s = strdup(text);
	if (s == NULL)
		return MESH_ENOMEM;
	line_text(s);
	h[m->nhist++] = s;
	return MESH_OK;
}

/* Quote an argument the way a shell would need it, so that a history line
 * can be pasted back into a shell. */
static int needs_quote(const char *s)
{
	if (*s == '\0')
		return 1;
	for (; *s; s++)
		if (!(isalnum((unsigned char)*s) || strchr("-_./=:,+%@", *s)))
			return 1;
	return 0;
}

char *mesh_argv_string(int argc, char *const argv[])
{
	size_t len = 1;
	for (int i = 0; i < argc; i++)
		len += 4 * strlen(argv[i]) + 3;
	char *buf = malloc(len), *p = buf;
	if (buf == NULL)
		return NULL;
	for (int i = 0; i < argc; i++) {
		const char *a = argv[i];
		if (i == 0) {
			const char *slash = strrchr(a, '/');
			if (slash)
				a = slash + 1;
		}
		if (i > 0)
			*p++ = ' ';
		if (needs_quote(a)) {
			*p++ = '\'';
			for (; *a; a++) {
				if (*a == '\'') {
					memcpy(p, "'\\''", 4);
					p += 4;
				} else {
					*p++ = *a;
				}
			}
			*p++ = '\'';
		} else {
			size_t n = strlen(a);
			memcpy(p, a, n);
			p += n;
		}
	}
	*p = '\0';
	return buf;
}

int mesh_history_argv(mesh *m, int argc, char *const argv[])
{
	char *buf = mesh_argv_string(argc, argv);
	if (buf == NULL)
		return MESH_ENOMEM;
	int st = mesh_history_add(m, buf);
	free(buf);
	return st;
}
