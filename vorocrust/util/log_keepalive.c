/* The keep-alive of vorocrust/log.h: a thread that repeats the last
 * progress line when the work has been silent for a period.
 *
 * The relay's callback runs inside vc_log's critical section (one call at
 * a time) and takes the keep-alive's mutex to note the line; the thread
 * reads the note under the mutex and logs through vc_log after releasing
 * it, so the two locks are never taken in the other order. */
#include "vorocrust/log.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "clock.h"

struct vc_log_keepalive {
    vc_logger log;    /* the caller's */
    double period;
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t wake;
    int stop;
    double t_last;    /* when the last VC_LOG_INFO line (or repeat) went out */
    double t_phase;   /* when the last line of the work went out */
    char last[512];   /* that line */
};

static void relay_fn(void *user, vc_log_level level, const char *message)
{
    vc_log_keepalive *k = user;
    if (level <= VC_LOG_INFO) {
        pthread_mutex_lock(&k->mu);
        k->t_last = vc_clock_seconds();
        snprintf(k->last, sizeof k->last, "%s", message);
        k->t_phase = k->t_last;
        pthread_mutex_unlock(&k->mu);
    }
    k->log.fn(k->log.user, level, message);
}

/* The repeat: the note of a line of the work, not of an earlier repeat. */
static void repeat_fn(void *user, vc_log_level level, const char *message)
{
    vc_log_keepalive *k = user;
    pthread_mutex_lock(&k->mu);
    k->t_last = vc_clock_seconds();
    pthread_mutex_unlock(&k->mu);
    k->log.fn(k->log.user, level, message);
}

static void *run(void *arg)
{
    vc_log_keepalive *k = arg;
    const double step = k->period / 8;
    pthread_mutex_lock(&k->mu);
    while (!k->stop) {
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        const double t = (double)until.tv_sec + 1e-9 * (double)until.tv_nsec + step;
        until.tv_sec = (time_t)t;
        until.tv_nsec = (long)((t - (double)until.tv_sec) * 1e9);
        pthread_cond_timedwait(&k->wake, &k->mu, &until);
        const double now = vc_clock_seconds();
        if (k->stop || now - k->t_last < k->period)
            continue;
        char line[640];
        if (k->last[0])
            snprintf(line, sizeof line, "%s (still at it: %.0f s)", k->last, now - k->t_phase);
        else
            snprintf(line, sizeof line, "working (%.0f s)", now - k->t_phase);
        k->t_last = now; /* no second repeat while this one waits for vc_log */
        pthread_mutex_unlock(&k->mu);
        const vc_logger repeat = {repeat_fn, k, k->log.max_level};
        vc_log(&repeat, VC_LOG_INFO, "%s", line);
        pthread_mutex_lock(&k->mu);
    }
    pthread_mutex_unlock(&k->mu);
    return NULL;
}

vc_log_keepalive *vc_log_keepalive_start(const vc_logger *log, double period, vc_logger *relay)
{
    static const vc_logger silent = {NULL, NULL, VC_LOG_ERROR};
    *relay = log ? *log : silent;
    if (!vc_log_enabled(log, VC_LOG_INFO) || !(period > 0))
        return NULL;
    vc_log_keepalive *k = calloc(1, sizeof *k);
    if (!k)
        return NULL;
    k->log = *log;
    k->period = period;
    k->t_last = k->t_phase = vc_clock_seconds();
    /* the waits time out on the monotonic clock */
    pthread_condattr_t ca;
    if (pthread_condattr_init(&ca) != 0) {
        free(k);
        return NULL;
    }
    const int cond_ok = pthread_condattr_setclock(&ca, CLOCK_MONOTONIC) == 0 &&
                        pthread_cond_init(&k->wake, &ca) == 0;
    pthread_condattr_destroy(&ca);
    const int mutex_ok = cond_ok && pthread_mutex_init(&k->mu, NULL) == 0;
    if (!mutex_ok || pthread_create(&k->thread, NULL, run, k) != 0) {
        if (mutex_ok)
            pthread_mutex_destroy(&k->mu);
        if (cond_ok)
            pthread_cond_destroy(&k->wake);
        free(k);
        return NULL;
    }
    *relay = (vc_logger){relay_fn, k, log->max_level};
    return k;
}

void vc_log_keepalive_stop(vc_log_keepalive *k)
{
    if (!k)
        return;
    pthread_mutex_lock(&k->mu);
    k->stop = 1;
    pthread_cond_signal(&k->wake);
    pthread_mutex_unlock(&k->mu);
    pthread_join(k->thread, NULL);
    pthread_cond_destroy(&k->wake);
    pthread_mutex_destroy(&k->mu);
    free(k);
}
