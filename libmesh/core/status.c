/* status.c - mesh_error_set, the one way a libmesh module reports a failure. */
#include "status.h"

#include <stdarg.h>
#include <stdio.h>

int mesh_error_vset(mesh_error *err, long line, int status, const char *fmt, va_list ap)
{
	if (err) {
		err->line = line;
		vsnprintf(err->msg, sizeof err->msg, fmt, ap);
	}
	return status;
}

int mesh_error_set(mesh_error *err, long line, int status, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int st = mesh_error_vset(err, line, status, fmt, ap);
	va_end(ap);
	return st;
}
