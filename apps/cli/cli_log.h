/* The CLI's logger: the library's messages on stderr. */
#ifndef VC_CLI_LOG_H
#define VC_CLI_LOG_H

#include "vorocrust/log.h"

/* Warnings and errors as "vorocrust: warning: MESSAGE", progress and
 * timings as they are; nothing above max_level. Also applies the
 * environment's VC_HUGE_PAGES=1 (the library's memory policy). */
void vc_cli_logger_init(vc_logger *log, vc_log_level max_level);

#endif
