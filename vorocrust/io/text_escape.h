/* Quoting bytes of an input file in a message: every byte but printable
 * ASCII (control characters, DEL, bytes >= 0x80) is written as \xNN, so
 * that a message stays one printable line whatever the file holds. File
 * names (vc_escape_name) keep bytes >= 0x80: UTF-8 names stay readable.
 * Internal to the readers. */
#ifndef VC_IO_TEXT_ESCAPE_H
#define VC_IO_TEXT_ESCAPE_H

#include <stddef.h>

/* Writes the escaped form of [s, s + n) into out (cap bytes, NUL
 * terminated, truncated with "..." when it does not fit); returns out. */
static inline const char *vc_escape_span_keep(const char *s, size_t n, char *out, size_t cap,
                                              int keep_high)
{
    static const char hex[] = "0123456789abcdef";
    size_t o = 0;
    if (cap == 0)
        return out;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        size_t need = (c < 0x20 || c == 0x7f || (c >= 0x80 && !keep_high)) ? 4 : 1;
        if (o + need + 4 > cap) { /* room for "..." and the NUL */
            if (o + 3 < cap) {
                out[o++] = '.';
                out[o++] = '.';
                out[o++] = '.';
            }
            break;
        }
        if (need == 1) {
            out[o++] = (char)c;
        } else {
            out[o++] = '\\';
            out[o++] = 'x';
            out[o++] = hex[c >> 4];
            out[o++] = hex[c & 15];
        }
    }
    out[o] = '\0';
    return out;
}

static inline const char *vc_escape_span(const char *s, size_t n, char *out, size_t cap)
{
    return vc_escape_span_keep(s, n, out, cap, 0);
}

/* The same for a NUL-terminated string. */
static inline const char *vc_escape_str(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    while (s[n])
        n++;
    return vc_escape_span_keep(s, n, out, cap, 0);
}

/* A file name: control characters escaped, other bytes kept. */
static inline const char *vc_escape_name(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    while (s[n])
        n++;
    return vc_escape_span_keep(s, n, out, cap, 1);
}

#endif
