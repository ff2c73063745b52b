/* vc_log_keepalive_start / _stop (vorocrust/log.h): while the work is
 * silent, the last progress line comes again at least every period, saying
 * how long it has been at it; a line of the work restarts the wait; nothing
 * comes after the stop; a silent logger starts no thread and relays as it
 * is; debug lines pass through without resetting the wait. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "vorocrust/log.h"

#include "test_check.h"

#define MAX_LINES 256

typedef struct captured {
    int n;
    double t[MAX_LINES];
    vc_log_level level[MAX_LINES];
    char line[MAX_LINES][160];
} captured;

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void sleep_for(double s)
{
    struct timespec t = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&t, &t) != 0)
        ;
}

/* vc_log calls it one message at a time */
static void capture(void *user, vc_log_level level, const char *message)
{
    captured *c = user;
    if (c->n < MAX_LINES) {
        c->t[c->n] = seconds();
        c->level[c->n] = level;
        snprintf(c->line[c->n], sizeof c->line[0], "%s", message);
    }
    c->n++;
}

int main(void)
{
    /* silent: no keep-alive, the relay is the logger itself */
    {
        vc_logger relay;
        CHECK(vc_log_keepalive_start(NULL, 0.1, &relay) == NULL && relay.fn == NULL);
        captured c = {0};
        const vc_logger warnings = {capture, &c, VC_LOG_WARNING};
        CHECK(vc_log_keepalive_start(&warnings, 0.1, &relay) == NULL);
        CHECK(relay.fn == capture && relay.user == &c && relay.max_level == VC_LOG_WARNING);
        vc_log_keepalive_stop(NULL); /* nothing */
    }
    captured c = {0};
    const vc_logger log = {capture, &c, VC_LOG_DEBUG};
    vc_logger relay;
    const double period = 0.2;
    vc_log_keepalive *k = vc_log_keepalive_start(&log, period, &relay);
    CHECK(k != NULL && relay.max_level == VC_LOG_DEBUG);
    const double t0 = seconds();
    vc_log(&relay, VC_LOG_INFO, "phase %d", 1);
    sleep_for(1.0);
    const int n1 = c.n;
    /* the first line, then a repeat every period or so (4 or 5 in the
     * second; a loaded machine may wake the thread late) */
    CHECK(n1 >= 3 && n1 <= 7);
    CHECK(!strcmp(c.line[0], "phase 1") && c.level[0] == VC_LOG_INFO);
    for (int i = 1; i < n1 && i < MAX_LINES; i++) {
        CHECK_MSG(!strncmp(c.line[i], "phase 1 (still at it: ", 22), c.line[i]);
        CHECK(c.level[i] == VC_LOG_INFO);
    }
    /* a debug line is relayed but is no progress: the repeats go on */
    vc_log(&relay, VC_LOG_DEBUG, "timing");
    CHECK(c.n == n1 + 1 && !strcmp(c.line[n1], "timing") && c.level[n1] == VC_LOG_DEBUG);
    sleep_for(0.5);
    CHECK(c.n >= n1 + 3);
    /* a new line of the work: repeated in turn, its own time counted */
    vc_log(&relay, VC_LOG_INFO, "phase 2");
    const int n2 = c.n;
    sleep_for(0.7);
    CHECK(c.n >= n2 + 2);
    CHECK_MSG(c.n > n2 && !strncmp(c.line[n2], "phase 2 (still at it: 0 s)", 26), c.line[n2]);
    vc_log_keepalive_stop(k);
    const int n3 = c.n;
    const double t_stop = seconds();
    sleep_for(0.5);
    CHECK(c.n == n3); /* nothing after the stop */
    /* never a gap of much more than the period (without the keep-alive:
     * 1 s); room for a loaded machine's late wake-ups */
    double gap = c.t[0] - t0;
    for (int i = 1; i < c.n && i < MAX_LINES; i++)
        gap = c.t[i] - c.t[i - 1] > gap ? c.t[i] - c.t[i - 1] : gap;
    gap = t_stop - c.t[n3 - 1] > gap ? t_stop - c.t[n3 - 1] : gap;
    CHECK_MSG(gap <= 2.5 * period, "a gap far longer than the period");
    if (failures == 0)
        printf("test_log_keepalive: all checks passed (%d lines, longest gap %.3f s)\n", c.n, gap);
    return failures ? 1 : 0;
}
