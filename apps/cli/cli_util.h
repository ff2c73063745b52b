/* Small helpers the sub-commands share. */
#ifndef VC_CLI_UTIL_H
#define VC_CLI_UTIL_H

/* Monotonic clock in seconds. */
double vc_cli_now(void);

/* A finite number filling the whole string; 0 on success. */
int vc_cli_parse_double(const char *s, double *out);

/* A base-10 integer in [lo, hi] filling the whole string; 0 on success. */
int vc_cli_parse_int(const char *s, long lo, long hi, long *out);

/* Whether the directory that would hold path exists and is writable. */
int vc_cli_directory_writable(const char *path);

#endif
