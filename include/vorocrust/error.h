/* Error reporting convention shared by every vorocrust function.
 *
 * Functions that can fail return 0 on success and a non-zero VC_E* code on
 * failure, and fill a caller-provided vc_error with one human-readable line
 * (no trailing newline) that names the file or object and the problem. */
#ifndef VORO_CRUST_ERROR_H
#define VORO_CRUST_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

enum {
    VC_OK = 0,
    VC_EIO = 1,       /* file missing, unreadable or unwritable */
    VC_EFORMAT = 2,   /* unsupported or malformed file */
    VC_EINPUT = 3,    /* input readable but unusable (NaN, open surface, ...) */
    VC_EPARAM = 4,    /* absurd parameter */
    VC_ENOMEM = 5,
    VC_EINTERNAL = 6  /* an invariant of the library was violated */
};

#define VC_ERROR_LEN 512

typedef struct vc_error {
    int code;
    char msg[VC_ERROR_LEN];
} vc_error;

/* Sets err->code and formats err->msg (printf-style); returns code.
 * err may be NULL. */
int vc_error_set(vc_error *err, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
