/* vc_log: formats a message and hands it to the caller's callback (see
 * vorocrust/log.h). */
#include "vorocrust/log.h"

#include <stdarg.h>
#include <stdio.h>

int vc_log_enabled(const vc_logger *log, vc_log_level level)
{
    return log && log->fn && level <= log->max_level;
}

void vc_log(const vc_logger *log, vc_log_level level, const char *fmt, ...)
{
    if (!vc_log_enabled(log, level))
        return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    /* the header promises one call at a time, whichever thread logs */
#pragma omp critical(vc_log_callback)
    log->fn(log->user, level, line);
}
