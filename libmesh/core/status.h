/* status.h - how every libmesh function reports a failure: a status code
 * (MESH_OK or a MESH_E* code) and, through a mesh_error the caller owns,
 * the input line it refers to and a message.  The library never prints and
 * never exits.  The lowest file of the library: everything else may use it,
 * it uses nothing of the library. */
#ifndef TIS_STATUS_H
#define TIS_STATUS_H

#include <stdarg.h>

enum mesh_status {
	MESH_OK = 0,
	MESH_EOF = -1,     /* mesh_read: no further mesh in the stream */
	MESH_EINVAL = 1,   /* malformed or invalid input */
	MESH_ENOMEM = 2,   /* allocation failed */
	MESH_EIO = 3,      /* read or write error */
	MESH_ENOCONV = 4,  /* an iterative method did not reach its tolerance */
	MESH_EDOM = 5,     /* argument out of range */
	MESH_ETOOBIG = 6   /* the job needs more memory than the caller allows
	                      (refused before anything is allocated) */
};

typedef struct {
	long line;         /* input line the error refers to, 0 if none */
	char msg[240];     /* lowercase, no full stop */
} mesh_error;

/* Fill err (if not NULL) with line and a printf-style message, and return
 * status: the one way every libmesh module reports a failure. */
int mesh_error_set(mesh_error *err, long line, int status, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
/* The same with a va_list, for a module's own error wrappers. */
int mesh_error_vset(mesh_error *err, long line, int status, const char *fmt, va_list ap)
	__attribute__((format(printf, 4, 0)));

#endif
