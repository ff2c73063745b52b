/* The CLI's logger: the library's messages on stderr. */
#ifndef VC_CLI_LOG_H
#define VC_CLI_LOG_H

#include "vorocrust/log.h"

/* Warnings and errors as "vorocrust: warning: MESSAGE", progress and
 * timings as they are; nothing above max_level. Also applies the
 * environment's VC_HUGE_PAGES=1 (the library's memory policy). */
void vc_cli_logger_init(vc_logger *log, vc_log_level max_level);

/* The keep-alive's period (vc_log_keepalive_start): a progress line at
 * least every 2 s (issue 16), with room for the thread's wake-ups. */
#define VC_CLI_KEEPALIVE 1.5
/* Meshes of this many cells or more take a second or more to check and
 * write: each step says so. */
#define VC_CLI_PROGRESS_CELLS 50000

#endif
