/* Logging and progress: the library never writes to a stream itself; it
 * hands every message to the caller's callback.
 *
 * A stage that can take long says what it is doing at VC_LOG_INFO (one line
 * every few seconds at most: "mesh: sliver elimination 3: ..."), problems it
 * worked around at VC_LOG_WARNING, and phase timings at VC_LOG_DEBUG. A
 * message is one line without its trailing newline. The callback may be
 * called from any thread, but never from two at once for one logger. */
#ifndef VORO_CRUST_LOG_H
#define VORO_CRUST_LOG_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vc_log_level {
    VC_LOG_ERROR = 0,
    VC_LOG_WARNING = 1,
    VC_LOG_INFO = 2,  /* progress */
    VC_LOG_DEBUG = 3  /* phase timings and counters */
} vc_log_level;

typedef void (*vc_log_fn)(void *user, vc_log_level level, const char *message);

/* Messages above max_level are not formatted at all. A NULL logger, or one
 * whose fn is NULL, is silent. */
typedef struct vc_logger {
    vc_log_fn fn;
    void *user;
    vc_log_level max_level;
} vc_logger;

/* Sends one printf-style message to log (nothing when log is silent or
 * level is above its max_level). */
void vc_log(const vc_logger *log, vc_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* 1 when vc_log(log, level, ...) would deliver the message. */
int vc_log_enabled(const vc_logger *log, vc_log_level level);

/* A keep-alive for long work (vorocrust/util/log_keepalive.c): *relay is
 * set to a logger that forwards every message to log and notes each
 * VC_LOG_INFO line; while the keep-alive runs, a thread of its own sends
 * one more whenever `period` seconds (> 0) pass without one: the last line
 * again, with how long it has been at it ("mesh: interior octree (still
 * at it: 4 s)"), so that a phase that says nothing for a while (a large
 * mesh's checks, its writing) is not mistaken for a hang. Pass *relay to
 * the work; log itself must outlive the keep-alive. Returns NULL, with
 * *relay a plain copy of log, when log would not deliver VC_LOG_INFO or
 * the thread cannot be started. */
typedef struct vc_log_keepalive vc_log_keepalive;
vc_log_keepalive *vc_log_keepalive_start(const vc_logger *log, double period, vc_logger *relay);
/* Stops the thread (no line after this returns) and frees k (NULL: nothing). */
void vc_log_keepalive_stop(vc_log_keepalive *k);

#ifdef __cplusplus
}
#endif
#endif
