/* Seeds as CSV: a header line, then rows "x,y,z[,label]".
 *
 * The reader loads the whole file and parses it in place (each field copied
 * out before strtod, see util/number_span.h), which keeps a million rows well under a second. Blank lines are skipped, CRLF
 * line ends and a UTF-8 byte-order mark are accepted. */
#include "vorocrust/seeds.h"
#include "vorocrust/io.h"
#include "io/csv_rows.h"
#include "io/text_escape.h"
#include "util/number_span.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int vc_seeds_alloc(vc_seeds *s, int64_t n, vc_error *err)
{
    s->n = 0;
    s->xyz = NULL;
    s->label = NULL;
    if (n < 0)
        return vc_error_set(err, VC_EPARAM, "vc_seeds_alloc: negative count %" PRId64, n);
    if ((uint64_t)n > SIZE_MAX / (3 * sizeof(double)))
        return vc_error_set(err, VC_ENOMEM, "vc_seeds_alloc: %" PRId64 " seeds is too many", n);
    size_t k = n > 0 ? (size_t)n : 1;
    s->xyz = malloc(3 * sizeof(double) * k);
    s->label = malloc(sizeof(int32_t) * k);
    if (!s->xyz || !s->label) {
        vc_seeds_free(s);
        return vc_error_set(err, VC_ENOMEM, "out of memory for %" PRId64 " seeds", n);
    }
    for (int64_t i = 0; i < n; ++i)
        s->label[i] = 1;
    s->n = n;
    return VC_OK;
}

int vc_seeds_concat(const vc_seeds *a, const vc_seeds *b, vc_seeds *out, vc_error *err)
{
    const int rc = vc_seeds_alloc(out, a->n + b->n, err);
    if (rc)
        return rc;
    memcpy(out->xyz, a->xyz, sizeof(double) * 3 * (size_t)a->n);
    memcpy(out->label, a->label, sizeof(int32_t) * (size_t)a->n);
    memcpy(out->xyz + 3 * a->n, b->xyz, sizeof(double) * 3 * (size_t)b->n);
    memcpy(out->label + a->n, b->label, sizeof(int32_t) * (size_t)b->n);
    return VC_OK;
}

void vc_seeds_free(vc_seeds *s)
{
    if (!s)
        return;
    free(s->xyz);
    free(s->label);
    s->xyz = NULL;
    s->label = NULL;
    s->n = 0;
}

/* ---- reading --------------------------------------------------------- */

/* Reads the whole stream into a NUL-terminated buffer. */
static char *seeds_slurp(FILE *fp, size_t *len_out, int *errno_out)
{
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap + 1);
    if (!buf)
        return NULL;
    for (;;) {
        if (len == cap) {
            if (cap > SIZE_MAX / 4) {
                free(buf);
                return NULL;
            }
            char *nb = realloc(buf, 2 * cap + 1);
            if (!nb) {
                free(buf);
                return NULL;
            }
            buf = nb;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, fp);
        len += got;
        if (got == 0) {
            if (ferror(fp)) {
                *errno_out = errno ? errno : EIO;
                free(buf);
                return NULL;
            }
            break;
        }
    }
    buf[len] = '\0';
    *len_out = len;
    return buf;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Field text for messages: at most 40 characters, control characters
 * escaped as \xNN (uses a local char shown[FIELD_SHOW_CAP]). */
#define FIELD_SHOW_CAP 176
#define FIELD_SHOW(b, e) vc_escape_span((b), (size_t)((e) - (b) > 40 ? 40 : (e) - (b)), shown, sizeof shown)

/* Bounds of the next field of a line: [*fs, *fe) trimmed; returns the
 * position after the field (its ',' or the line end). */
static const char *next_field(const char *p, const char *eol, const char **fs,
                              const char **fe)
{
    const char *e = p;
    while (e < eol && *e != ',')
        ++e;
    const char *b = p;
    while (b < e && is_blank(*b))
        ++b;
    const char *t = e;
    while (t > b && is_blank(t[-1]))
        --t;
    *fs = b;
    *fe = t;
    return e;
}

/* Does the trimmed field parse completely as a number? */
static int field_is_number(const char *fs, const char *fe, double *v)
{
    if (fs == fe)
        return 0;
    int erange;
    return vc_strtod_span(fs, fe, v, &erange) == (size_t)(fe - fs);
}

int vc_seeds_read_csv(const char *orig_path, vc_seeds *out, vc_error *err)
{
    const char *path = orig_path;
    out->n = 0;
    out->xyz = NULL;
    out->label = NULL;
    if (!path)
        return vc_error_set(err, VC_EPARAM, "vc_seeds_read_csv: NULL path");
    char shown[FIELD_SHOW_CAP];
    char name[VC_ERROR_LEN];
    vc_escape_name(path, name, sizeof name);
    path = name; /* only messages use it from here on */
    FILE *fp = fopen(orig_path, "rb");
    if (!fp)
        return vc_error_set(err, VC_EIO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(fp), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(fp);
        return vc_error_set(err, VC_EIO, "%s: is a directory", path);
    }
    size_t len = 0;
    int rerr = 0;
    char *buf = seeds_slurp(fp, &len, &rerr);
    fclose(fp);
    if (!buf) {
        if (rerr)
            return vc_error_set(err, VC_EIO, "%s: cannot read: %s", path, strerror(rerr));
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory reading the file", path);
    }

    const char *p = buf, *end = buf + len;
    if (len >= 3 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB &&
        (unsigned char)p[2] == 0xBF)
        p += 3; /* UTF-8 byte-order mark */

    /* Upper bound on the number of rows: the number of lines. */
    int64_t nlines = 1;
    for (const char *q = p; (q = memchr(q, '\n', (size_t)(end - q))) != NULL; ++q)
        ++nlines;

    vc_seeds s;
    int rc = vc_seeds_alloc(&s, nlines, err);
    if (rc) {
        free(buf);
        return rc;
    }

    int64_t line = 0, n = 0;
    int have_header = 0, nfields = 0;
    int64_t first_row_line = 0;
    rc = VC_OK;
    while (p < end || (p == end && line == 0)) {
        ++line;
        const char *eol = memchr(p, '\n', (size_t)(end - p));
        if (!eol)
            eol = end;
        const char *next = eol < end ? eol + 1 : end;
        const char *le = eol;
        if (le > p && le[-1] == '\r')
            --le;
        const char *q = p;
        while (q < le && (is_blank(*q) || *q == '\r'))
            ++q;
        if (q == le) { /* blank line */
            p = next;
            if (p == end)
                break;
            continue;
        }
        if (!have_header) {
            const char *fs, *fe;
            double v;
            next_field(p, le, &fs, &fe);
            if (field_is_number(fs, fe, &v)) {
                rc = vc_error_set(err, VC_EFORMAT,
                                  "%s:%" PRId64 ": missing header line (expected a first "
                                  "line such as x,y,z or x,y,z,label)", path, line);
                break;
            }
            have_header = 1;
            p = next;
            continue;
        }

        /* a data row */
        double xyz[3];
        long long lab = 1;
        int k = 0;
        const char *r = p;
        for (;;) {
            const char *fs, *fe;
            const char *fend = next_field(r, le, &fs, &fe);
            if (k < 3) {
                if (!field_is_number(fs, fe, &xyz[k])) {
                    rc = vc_error_set(err, VC_EFORMAT,
                                      "%s:%" PRId64 ": field %d \"%s\" is not a number",
                                      path, line, k + 1, FIELD_SHOW(fs, fe));
                    break;
                }
                if (!isfinite(xyz[k])) {
                    rc = vc_error_set(err, VC_EINPUT,
                                      "%s:%" PRId64 ": field %d \"%s\" is not finite",
                                      path, line, k + 1, FIELD_SHOW(fs, fe));
                    break;
                }
            } else if (k == 3) {
                int erange = 0;
                size_t used = (fs < fe) ? vc_strtoll_span(fs, fe, &lab, &erange) : 0;
                if (fs == fe || used != (size_t)(fe - fs) || erange || lab < INT32_MIN ||
                    lab > INT32_MAX) {
                    rc = vc_error_set(err, VC_EFORMAT,
                                      "%s:%" PRId64 ": label \"%s\" is not a 32-bit "
                                      "integer", path, line, FIELD_SHOW(fs, fe));
                    break;
                }
            }
            ++k;
            if (fend >= le)
                break;
            r = fend + 1;
        }
        if (rc)
            break;
        if (nfields == 0) {
            if (k != 3 && k != 4) {
                rc = vc_error_set(err, VC_EFORMAT,
                                  "%s:%" PRId64 ": expected 3 or 4 fields (x,y,z[,label]), "
                                  "found %d", path, line, k);
                break;
            }
            nfields = k;
            first_row_line = line;
        } else if (k != nfields) {
            rc = vc_error_set(err, VC_EFORMAT,
                              "%s:%" PRId64 ": expected %d fields like line %" PRId64
                              ", found %d", path, line, nfields, first_row_line, k);
            break;
        }
        s.xyz[3 * n + 0] = xyz[0];
        s.xyz[3 * n + 1] = xyz[1];
        s.xyz[3 * n + 2] = xyz[2];
        s.label[n] = (int32_t)lab;
        ++n;
        p = next;
        if (p == end)
            break;
    }
    free(buf);
    if (!rc && !have_header)
        rc = vc_error_set(err, VC_EFORMAT, "%s: empty file (expected a header line and "
                          "rows x,y,z[,label])", path);
    if (rc) {
        vc_seeds_free(&s);
        return rc;
    }
    s.n = n;
    *out = s;
    return VC_OK;
}

/* ---- writing --------------------------------------------------------- */

#define SEEDS_ROWS_PER_CHUNK 1024
#define SEEDS_ROW_MAX 128 /* 3 * 24 chars + an int32 + separators */

static int seed_row(const void *ctx, int64_t i, char *out, size_t room)
{
    const vc_seeds *s = ctx;
    const double *x = s->xyz + 3 * i;
    return snprintf(out, room, "%.17g,%.17g,%.17g,%" PRId32 "\n", x[0], x[1], x[2],
                    s->label ? s->label[i] : (int32_t)1);
}

int vc_seeds_write_csv(const char *path, const vc_seeds *s, vc_error *err)
{
    if (!path || !s)
        return vc_error_set(err, VC_EPARAM, "vc_seeds_write_csv: NULL argument");
    if (s->n < 0 || (s->n > 0 && !s->xyz))
        return vc_error_set(err, VC_EPARAM, "%s: invalid seed set", path);
    return vc_csv_write_rows(path, "x,y,z,label\n", s->n, SEEDS_ROW_MAX, SEEDS_ROWS_PER_CHUNK,
                             seed_row, s, err);
}
