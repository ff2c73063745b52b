/* The CLI's logger (see cli_log.h). */
#include "cli_log.h"

#include <stdio.h>
#include <stdlib.h>

#include "vorocrust/voronoi.h"

static void to_stderr(void *user, vc_log_level level, const char *message)
{
    (void)user;
    if (level <= VC_LOG_WARNING)
        fprintf(stderr, "vorocrust: %s%s\n", level == VC_LOG_WARNING ? "warning: " : "",
                message);
    else
        fprintf(stderr, "%s\n", message);
}

void vc_cli_logger_init(vc_logger *log, vc_log_level max_level)
{
    log->fn = to_stderr;
    log->user = NULL;
    log->max_level = max_level;
    const char *huge = getenv("VC_HUGE_PAGES");
    vc_voronoi_set_huge_pages(huge && huge[0] == '1');
}
