/* status.c - mesh_error_set, the one way a libmesh module reports a failure. */
#include "status.h"

#include <stdarg.h>
#include <stdio.h>

int mesh_error_set(mesh_error *err, long line, int status, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		err->line = line;
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof err->msg, fmt, ap);
		va_end(ap);
	}
	return status;
}
