/* VTK XML UnstructuredGrid reader for polyhedra and tetrahedra.
 *
 * The whole file is read into memory. The XML part is scanned tag by tag
 * (only what a .vtu needs: VTKFile, Piece, Points, Cells, DataArray and
 * AppendedData; other elements such as InformationKey are passed over)
 * until the appended-data marker '_', after which the bytes are binary.
 *
 * Every binary array, inline or appended, is [header][data], the header
 * words being UInt32 or UInt64 (header_type):
 *   uncompressed: one word, the byte count, then the bytes;
 *   zlib:         nblocks, block size, size of the last block (0 = full),
 *                 the compressed size of every block, then the blocks.
 * Base64 text (inline arrays, appended data with encoding="base64") is
 * decoded as a stream of 4-character groups; VTK encodes a compressed
 * array's header and its data separately, so a group ending in '=' padding
 * may be followed by more groups, and the stream decoder simply carries
 * on. Numbers in ascii arrays are parsed with the number_span helpers (no
 * strtod on the big buffer). */
#include "vorocrust/vtu_reader.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "io/text_escape.h"
#include "util/number_span.h"

/* ---- small text helpers on [p, e) spans (no str* on the big buffer) ----- */

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

static const char *find_char(const char *p, const char *e, char c)
{
    const char *q = p < e ? memchr(p, c, (size_t)(e - p)) : NULL;
    return q ? q : e;
}

static const char *find_str(const char *p, const char *e, const char *s)
{
    size_t n = strlen(s);
    while (p + n <= e) {
        const char *q = memchr(p, s[0], (size_t)(e - p));
        if (!q || q + n > e)
            return e;
        if (!memcmp(q, s, n))
            return q;
        p = q + 1;
    }
    return e;
}

static int span_eq(const char *b, const char *e, const char *s)
{
    size_t n = strlen(s);
    return (size_t)(e - b) == n && !memcmp(b, s, n);
}

/* ---- XML tags ------------------------------------------------------------ */

#define MAX_ATTRS 24

typedef struct xml_tag {
    const char *name_b, *name_e;
    int closing;       /* </name> */
    int self_closing;  /* <name ... /> */
    int n_attr;
    const char *key_b[MAX_ATTRS], *key_e[MAX_ATTRS];
    const char *val_b[MAX_ATTRS], *val_e[MAX_ATTRS];
    const char *end;   /* just after '>' */
} xml_tag;

/* Parses the tag starting at p ('<'). Returns 0, or -1 when malformed. */
static int xml_parse_tag(const char *p, const char *e, xml_tag *t)
{
    memset(t, 0, sizeof *t);
    p++;
    if (p < e && *p == '/') {
        t->closing = 1;
        p++;
    }
    t->name_b = p;
    while (p < e && !is_space(*p) && *p != '>' && *p != '/')
        p++;
    t->name_e = p;
    if (t->name_e == t->name_b)
        return -1;
    for (;;) {
        while (p < e && is_space(*p))
            p++;
        if (p >= e)
            return -1;
        if (*p == '>') {
            t->end = p + 1;
            return 0;
        }
        if (*p == '/') {
            if (p + 1 < e && p[1] == '>') {
                t->self_closing = 1;
                t->end = p + 2;
                return 0;
            }
            return -1;
        }
        const char *kb = p;
        while (p < e && !is_space(*p) && *p != '=' && *p != '>')
            p++;
        const char *ke = p;
        while (p < e && is_space(*p))
            p++;
        if (p >= e || *p != '=')
            return -1;
        p++;
        while (p < e && is_space(*p))
            p++;
        if (p >= e || (*p != '"' && *p != '\''))
            return -1;
        char quote = *p++;
        const char *vb = p;
        p = find_char(p, e, quote);
        if (p >= e)
            return -1;
        if (t->n_attr < MAX_ATTRS) {
            t->key_b[t->n_attr] = kb;
            t->key_e[t->n_attr] = ke;
            t->val_b[t->n_attr] = vb;
            t->val_e[t->n_attr] = p;
            t->n_attr++;
        }
        p++;
    }
}

static int tag_is(const xml_tag *t, const char *name)
{
    return span_eq(t->name_b, t->name_e, name);
}

/* Copies attribute `key` into buf (truncated to cap - 1); returns 1 if found. */
static int tag_attr(const xml_tag *t, const char *key, char *buf, size_t cap)
{
    for (int i = 0; i < t->n_attr; i++)
        if (span_eq(t->key_b[i], t->key_e[i], key)) {
            size_t n = (size_t)(t->val_e[i] - t->val_b[i]);
            if (n >= cap)
                n = cap - 1;
            memcpy(buf, t->val_b[i], n);
            buf[n] = 0;
            return 1;
        }
    return 0;
}

/* ---- the arrays a .vtu needs ----------------------------------------------- */

enum {
    ARR_POINTS, ARR_CONN, ARR_OFFSETS, ARR_TYPES, ARR_FACES, ARR_FACEOFFSETS,
    ARR_FACE_CONN, ARR_FACE_OFFSETS, ARR_POLY_TO_FACES, ARR_POLY_OFFSETS,
    ARR_SEED_POINT, /* CellData, optional: each cell's seed (vorocrust's meshes) */
    ARR_COUNT
};
static const char *const array_names[ARR_COUNT] = {
    "Points", "connectivity", "offsets", "types", "faces", "faceoffsets",
    "face_connectivity", "face_offsets", "polyhedron_to_faces", "polyhedron_offsets",
    "seed_point"};

typedef enum { FMT_ASCII, FMT_BINARY, FMT_APPENDED } array_format;

typedef struct array_info {
    int present;
    char type[16];
    int ncomp;
    array_format format;
    uint64_t offset;         /* appended */
    const char *text_b, *text_e; /* inline content (ascii or base64) */
} array_info;

typedef struct vtu_file {
    const char *path;
    char *buf;
    size_t size;
    int header64;            /* header_type UInt64 */
    int zlib;                /* vtkZLibDataCompressor */
    int appended_base64;
    const char *app_b, *app_e; /* appended data: after '_' .. end */
    int64_t n_points, n_cells;
    array_info arr[ARR_COUNT];
} vtu_file;

static int type_size(const char *type, int *is_float, int *is_signed)
{
    static const struct { const char *name; int size, flt, sgn; } types[] = {
        {"Int8", 1, 0, 1},   {"UInt8", 1, 0, 0},   {"Int16", 2, 0, 1},  {"UInt16", 2, 0, 0},
        {"Int32", 4, 0, 1},  {"UInt32", 4, 0, 0},  {"Int64", 8, 0, 1},  {"UInt64", 8, 0, 0},
        {"Float32", 4, 1, 1}, {"Float64", 8, 1, 1}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcmp(type, types[i].name)) {
            *is_float = types[i].flt;
            *is_signed = types[i].sgn;
            return types[i].size;
        }
    return 0;
}

/* ---- byte sources: raw bytes or a base64 stream ----------------------------- */

typedef struct byte_source {
    int base64;
    const unsigned char *p, *e; /* raw: bytes; base64: text */
    unsigned char pend[3];
    int npend, ipend;
} byte_source;

static int b64_value(unsigned char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

/* Decodes the next 4-character group into s->pend; returns 0, or -1 at the
 * end of the text or on a bad character. */
static int b64_group(byte_source *s)
{
    int v[4], n = 0, pad = 0;
    while (n < 4) {
        while (s->p < s->e && is_space((char)*s->p))
            s->p++;
        if (s->p >= s->e)
            return -1;
        unsigned char c = *s->p++;
        if (c == '=') {
            v[n++] = 0;
            pad++;
        } else {
            int x = b64_value(c);
            if (x < 0 || pad)
                return -1;
            v[n++] = x;
        }
    }
    if (pad > 2)
        return -1;
    uint32_t w = (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 | (uint32_t)v[2] << 6 | (uint32_t)v[3];
    s->pend[0] = (unsigned char)(w >> 16);
    s->pend[1] = (unsigned char)(w >> 8);
    s->pend[2] = (unsigned char)w;
    s->npend = 3 - pad;
    s->ipend = 0;
    return 0;
}

/* Reads exactly n bytes; returns 0, or -1 when the source ends first. */
static int src_read(byte_source *s, void *out, size_t n)
{
    unsigned char *o = out;
    if (n == 0)
        return 0; /* out may be NULL (an empty block) */
    if (!s->base64) {
        if ((size_t)(s->e - s->p) < n)
            return -1;
        memcpy(o, s->p, n);
        s->p += n;
        return 0;
    }
    while (n > 0) {
        if (s->ipend < s->npend) {
            size_t k = (size_t)(s->npend - s->ipend);
            if (k > n)
                k = n;
            memcpy(o, s->pend + s->ipend, k);
            s->ipend += (int)k;
            o += k;
            n -= k;
            continue;
        }
        if (b64_group(s) != 0)
            return -1;
    }
    return 0;
}

static int src_word(byte_source *s, int header64, uint64_t *w)
{
    if (header64)
        return src_read(s, w, 8);
    uint32_t v;
    if (src_read(s, &v, 4))
        return -1;
    *w = v;
    return 0;
}

/* vc_error_set for a message about the file who: "WHO: MESSAGE". The
 * message may quote bytes of a damaged file: they are escaped as \xNN as in
 * the other readers (io/text_escape.h), and so are control characters of the
 * file name (whose UTF-8 is kept), so that it stays one printable line. */
static int vtu_fail(vc_error *err, int code, const char *who, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static int vtu_fail(vc_error *err, int code, const char *who, const char *fmt, ...)
{
    if (!err)
        return code;
    char raw[sizeof err->msg], text[sizeof err->msg], name[sizeof err->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    vc_escape_span(raw, strlen(raw), text, sizeof text);
    const char *pieces[3] = {who ? vc_escape_name(who, name, sizeof name) : "", who ? ": " : "",
                             text};
    size_t o = 0;
    for (int k = 0; k < 3; k++)
        for (const char *q = pieces[k]; *q && o + 1 < sizeof err->msg; q++)
            err->msg[o++] = *q;
    err->msg[o] = '\0';
    err->code = code;
    return code;
}

#define FAIL(code, who, ...) vtu_fail(err, code, who, __VA_ARGS__)

/* Decodes the binary array behind src into a new buffer. */
static int decode_binary(const vtu_file *f, const char *name, byte_source *src,
                         unsigned char **out, size_t *nbytes, vc_error *err)
{
    *out = NULL;
    *nbytes = 0;
    if (!f->zlib) {
        uint64_t n;
        if (src_word(src, f->header64, &n))
            return FAIL(VC_EFORMAT, f->path, "array '%s': truncated data (no size header)", name);
        if (n > (uint64_t)f->size * 2 + 64)
            return FAIL(VC_EFORMAT, f->path, "array '%s': size header %" PRIu64 " exceeds the file",
                        name, n);
        unsigned char *b = malloc(n ? (size_t)n : 1);
        if (!b)
            return FAIL(VC_ENOMEM, f->path, "out of memory");
        if (src_read(src, b, (size_t)n)) {
            free(b);
            return FAIL(VC_EFORMAT, f->path, "array '%s': truncated data (%" PRIu64 " bytes "
                        "announced)", name, n);
        }
        *out = b;
        *nbytes = (size_t)n;
        return VC_OK;
    }
    uint64_t nb, bs, last;
    if (src_word(src, f->header64, &nb) || src_word(src, f->header64, &bs) ||
        src_word(src, f->header64, &last))
        return FAIL(VC_EFORMAT, f->path, "array '%s': truncated compression header", name);
    if (nb > (uint64_t)f->size || (nb > 0 && (bs == 0 || last > bs)) ||
        (nb > 0 && bs > ((uint64_t)1 << 40)))
        return FAIL(VC_EFORMAT, f->path, "array '%s': bad compression header (%" PRIu64
                    " blocks of %" PRIu64 " bytes, last %" PRIu64 ")", name, nb, bs, last);
    if (nb > 1 && nb - 1 > (UINT64_MAX - bs) / bs)
        return FAIL(VC_EFORMAT, f->path, "array '%s': bad compression header (%" PRIu64
                    " blocks of %" PRIu64 " bytes)", name, nb, bs);
    uint64_t total = nb == 0 ? 0 : (nb - 1) * bs + (last ? last : bs);
    if (total / 1100 > (uint64_t)f->size + 1024) /* zlib cannot compress beyond ~1000:1 */
        return FAIL(VC_EFORMAT, f->path, "array '%s': bad compression header (%" PRIu64
                    " bytes from a %zu-byte file)", name, total, f->size);
    if (total > SIZE_MAX / 2)
        return FAIL(VC_ENOMEM, f->path, "array '%s': %" PRIu64 " bytes is too large", name, total);
    uint64_t *csize = malloc(sizeof *csize * (size_t)(nb ? nb : 1));
    unsigned char *b = malloc(total ? (size_t)total : 1);
    unsigned char *cbuf = NULL;
    size_t ccap = 0;
    int rc = VC_OK;
    if (!csize || !b) {
        rc = FAIL(VC_ENOMEM, f->path, "out of memory");
        goto done;
    }
    for (uint64_t i = 0; i < nb; i++)
        if (src_word(src, f->header64, &csize[i]) || csize[i] > (uint64_t)f->size) {
            rc = FAIL(VC_EFORMAT, f->path, "array '%s': truncated compression header", name);
            goto done;
        }
    for (uint64_t i = 0; i < nb; i++) {
        if (csize[i] > ccap) {
            free(cbuf);
            ccap = (size_t)csize[i];
            cbuf = malloc(ccap);
            if (!cbuf) {
                rc = FAIL(VC_ENOMEM, f->path, "out of memory");
                goto done;
            }
        }
        if (src_read(src, cbuf, (size_t)csize[i])) {
            rc = FAIL(VC_EFORMAT, f->path, "array '%s': truncated compressed data", name);
            goto done;
        }
        uint64_t want = (i + 1 < nb || last == 0) ? bs : last;
        uLongf got = (uLongf)want;
        int zr = uncompress(b + i * bs, &got, cbuf, (uLong)csize[i]);
        if (zr != Z_OK || got != want) {
            rc = FAIL(VC_EFORMAT, f->path, "array '%s': corrupt zlib block %" PRIu64 " (%s)",
                      name, i, zr == Z_OK ? "wrong size" : zError(zr));
            goto done;
        }
    }
    *out = b;
    *nbytes = (size_t)total;
    b = NULL;
done:
    free(csize);
    free(b);
    free(cbuf);
    return rc;
}

/* A decoded array: values as int64 or double. */
typedef struct values {
    int64_t n;
    int64_t *i;
    double *d;
} values;

static void values_free(values *v)
{
    free(v->i);
    free(v->d);
    memset(v, 0, sizeof *v);
}

/* Parses an ascii array's numbers. */
static int parse_ascii(const vtu_file *f, const char *name, const array_info *a, int as_float,
                       values *v, vc_error *err)
{
    size_t cap = 1024;
    int64_t n = 0;
    void *buf = malloc(cap * 8);
    if (!buf)
        return FAIL(VC_ENOMEM, f->path, "out of memory");
    const char *p = a->text_b, *e = a->text_e;
    for (;;) {
        while (p < e && is_space(*p))
            p++;
        if (p >= e)
            break;
        if ((size_t)n == cap) {
            void *nb = realloc(buf, cap * 2 * 8);
            if (!nb) {
                free(buf);
                return FAIL(VC_ENOMEM, f->path, "out of memory");
            }
            buf = nb;
            cap *= 2;
        }
        size_t used;
        int erange;
        if (as_float) {
            double x;
            used = vc_strtod_span(p, e, &x, &erange);
            ((double *)buf)[n] = x;
        } else {
            long long x;
            used = vc_strtoll_span(p, e, &x, &erange);
            ((int64_t *)buf)[n] = (int64_t)x;
        }
        if (used == 0 || erange || (p + used < e && !is_space(p[used]))) {
            const char *t = p;
            while (t < e && !is_space(*t) && t - p < 20)
                t++;
            free(buf);
            return FAIL(VC_EFORMAT, f->path, "array '%s': '%.*s' is not a%s number", name,
                        (int)(t - p), p, as_float ? "" : "n integer");
        }
        p += used;
        n++;
    }
    v->n = n;
    if (as_float)
        v->d = buf;
    else
        v->i = buf;
    return VC_OK;
}

/* Reads array k as integers (as_float = 0) or doubles. */
static int read_array(const vtu_file *f, int k, int as_float, values *v, vc_error *err)
{
    const array_info *a = &f->arr[k];
    const char *name = array_names[k];
    memset(v, 0, sizeof *v);
    int is_float, is_signed;
    int size = type_size(a->type, &is_float, &is_signed);
    if (!size)
        return FAIL(VC_EFORMAT, f->path, "array '%s': unsupported type '%s'", name, a->type);
    if (is_float && !as_float)
        return FAIL(VC_EFORMAT, f->path, "array '%s': type %s where integers are expected",
                    name, a->type);
    if (a->format == FMT_ASCII)
        return parse_ascii(f, name, a, as_float, v, err);

    byte_source src;
    memset(&src, 0, sizeof src);
    if (a->format == FMT_BINARY) {
        src.base64 = 1;
        src.p = (const unsigned char *)a->text_b;
        src.e = (const unsigned char *)a->text_e;
    } else {
        if (!f->app_b)
            return FAIL(VC_EFORMAT, f->path, "array '%s' is appended but the file has no "
                        "AppendedData", name);
        if (a->offset > (uint64_t)(f->app_e - f->app_b))
            return FAIL(VC_EFORMAT, f->path, "array '%s': offset %" PRIu64 " is past the end of "
                        "the appended data (truncated file?)", name, a->offset);
        src.base64 = f->appended_base64;
        src.p = (const unsigned char *)f->app_b + a->offset;
        src.e = (const unsigned char *)f->app_e;
    }
    unsigned char *bytes;
    size_t nbytes;
    int rc = decode_binary(f, name, &src, &bytes, &nbytes, err);
    if (rc)
        return rc;
    if (nbytes % (size_t)size) {
        free(bytes);
        return FAIL(VC_EFORMAT, f->path, "array '%s': %zu bytes is not a whole number of %s values",
                    name, nbytes, a->type);
    }
    int64_t n = (int64_t)(nbytes / (size_t)size);
    void *out = malloc((size_t)(n ? n : 1) * 8);
    if (!out) {
        free(bytes);
        return FAIL(VC_ENOMEM, f->path, "out of memory");
    }
    for (int64_t i = 0; i < n; i++) {
        const unsigned char *b = bytes + (size_t)i * (size_t)size;
        if (is_float) {
            double x;
            if (size == 4) {
                float y;
                memcpy(&y, b, 4);
                x = y;
            } else {
                memcpy(&x, b, 8);
            }
            ((double *)out)[i] = x;
            continue;
        }
        int64_t x = 0;
        switch (size) {
        case 1: x = is_signed ? (int64_t)(int8_t)b[0] : (int64_t)b[0]; break;
        case 2: { uint16_t y; memcpy(&y, b, 2); x = is_signed ? (int64_t)(int16_t)y : (int64_t)y; } break;
        case 4: { uint32_t y; memcpy(&y, b, 4); x = is_signed ? (int64_t)(int32_t)y : (int64_t)y; } break;
        default: {
            uint64_t y;
            memcpy(&y, b, 8);
            if (!is_signed && y > (uint64_t)INT64_MAX) {
                free(out);
                free(bytes);
                return FAIL(VC_EFORMAT, f->path, "array '%s': value %" PRIu64 " out of range",
                            name, y);
            }
            x = (int64_t)y;
        }
        }
        if (as_float)
            ((double *)out)[i] = (double)x;
        else
            ((int64_t *)out)[i] = x;
    }
    free(bytes);
    v->n = n;
    if (as_float)
        v->d = out;
    else
        v->i = out;
    return VC_OK;
}

/* ---- the XML structure ------------------------------------------------------ */

static int parse_count(const char *s, int64_t *out)
{
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (errno || end == s || v < 0)
        return -1;
    while (*end && is_space(*end))
        end++;
    if (*end)
        return -1;
    *out = (int64_t)v;
    return 0;
}

static int scan_xml(vtu_file *f, vc_error *err)
{
    const char *p = f->buf, *e = f->buf + f->size;
    int seen_vtkfile = 0, n_pieces = 0, in_points = 0, in_cells = 0, in_piece = 0, in_celldata = 0;
    char val[128];
    while (p < e) {
        p = find_char(p, e, '<');
        if (p >= e)
            break;
        if (e - p >= 2 && (p[1] == '?' || p[1] == '!')) {
            const char *q = (e - p >= 4 && !memcmp(p, "<!--", 4)) ? find_str(p, e, "-->")
                                                                  : find_char(p, e, '>');
            if (q >= e)
                return FAIL(VC_EFORMAT, f->path, "unterminated XML declaration or comment");
            p = q + 1;
            continue;
        }
        xml_tag t;
        if (xml_parse_tag(p, e, &t) != 0)
            return FAIL(VC_EFORMAT, f->path, "malformed XML tag at byte %td", p - f->buf);
        p = t.end;
        if (t.closing) {
            if (tag_is(&t, "Points"))
                in_points = 0;
            else if (tag_is(&t, "Cells"))
                in_cells = 0;
            else if (tag_is(&t, "CellData"))
                in_celldata = 0;
            else if (tag_is(&t, "Piece"))
                in_piece = 0;
            continue;
        }
        if (tag_is(&t, "VTKFile")) {
            seen_vtkfile = 1;
            if (!tag_attr(&t, "type", val, sizeof val) || strcmp(val, "UnstructuredGrid"))
                return FAIL(VC_EFORMAT, f->path, "not an UnstructuredGrid file (VTKFile type '%s')",
                            tag_attr(&t, "type", val, sizeof val) ? val : "");
            if (tag_attr(&t, "byte_order", val, sizeof val) && strcmp(val, "LittleEndian"))
                return FAIL(VC_EFORMAT, f->path, "byte_order '%s' is not supported (LittleEndian "
                            "only)", val);
            if (tag_attr(&t, "header_type", val, sizeof val)) {
                if (!strcmp(val, "UInt64"))
                    f->header64 = 1;
                else if (strcmp(val, "UInt32"))
                    return FAIL(VC_EFORMAT, f->path, "header_type '%s' is not UInt32 or UInt64",
                                val);
            }
            if (tag_attr(&t, "compressor", val, sizeof val) && val[0]) {
                if (!strcmp(val, "vtkZLibDataCompressor"))
                    f->zlib = 1;
                else
                    return FAIL(VC_EFORMAT, f->path, "compressor '%s' is not supported "
                                "(only vtkZLibDataCompressor)", val);
            }
        } else if (!seen_vtkfile) {
            return FAIL(VC_EFORMAT, f->path, "not a VTK XML file (no VTKFile element first)");
        } else if (tag_is(&t, "Piece")) {
            if (++n_pieces > 1)
                return FAIL(VC_EFORMAT, f->path, "more than one Piece (not supported)");
            in_piece = 1;
            if (!tag_attr(&t, "NumberOfPoints", val, sizeof val) || parse_count(val, &f->n_points) ||
                !tag_attr(&t, "NumberOfCells", val, sizeof val) || parse_count(val, &f->n_cells))
                return FAIL(VC_EFORMAT, f->path, "Piece without valid NumberOfPoints and "
                            "NumberOfCells");
            /* Far beyond any file (a point is 3 values, a cell an offset and
             * a type): refused here so that later count arithmetic (3 x
             * points, cells + 1) cannot overflow. */
            if (f->n_points > ((int64_t)1 << 52) || f->n_cells > ((int64_t)1 << 52))
                return FAIL(VC_EFORMAT, f->path, "Piece announces %" PRId64 " points and %" PRId64
                            " cells, beyond what a file can hold", f->n_points, f->n_cells);
        } else if (tag_is(&t, "Points") && !t.self_closing) {
            in_points = in_piece;
        } else if (tag_is(&t, "Cells") && !t.self_closing) {
            in_cells = in_piece;
        } else if (tag_is(&t, "CellData") && !t.self_closing) {
            in_celldata = in_piece;
        } else if (tag_is(&t, "DataArray") && (in_points || in_cells || in_celldata)) {
            int k = -1;
            if (in_points) {
                k = ARR_POINTS;
            } else if (in_celldata) {
                if (tag_attr(&t, "Name", val, sizeof val) && !strcmp(val, "seed_point"))
                    k = ARR_SEED_POINT;
            } else if (tag_attr(&t, "Name", val, sizeof val)) {
                for (int i = 1; i < ARR_SEED_POINT; i++)
                    if (!strcmp(val, array_names[i]))
                        k = i;
            }
            if (k < 0 || f->arr[k].present)
                continue;
            array_info *a = &f->arr[k];
            a->present = 1;
            if (!tag_attr(&t, "type", a->type, sizeof a->type))
                return FAIL(VC_EFORMAT, f->path, "array '%s' has no type", array_names[k]);
            a->ncomp = 1;
            if (tag_attr(&t, "NumberOfComponents", val, sizeof val)) {
                int64_t nc;
                if (parse_count(val, &nc) || nc < 1 || nc > 64)
                    return FAIL(VC_EFORMAT, f->path, "array '%s': bad NumberOfComponents '%s'",
                                array_names[k], val);
                a->ncomp = (int)nc;
            }
            if (!tag_attr(&t, "format", val, sizeof val))
                return FAIL(VC_EFORMAT, f->path, "array '%s' has no format", array_names[k]);
            if (!strcmp(val, "ascii"))
                a->format = FMT_ASCII;
            else if (!strcmp(val, "binary"))
                a->format = FMT_BINARY;
            else if (!strcmp(val, "appended"))
                a->format = FMT_APPENDED;
            else
                return FAIL(VC_EFORMAT, f->path, "array '%s': unknown format '%s'",
                            array_names[k], val);
            if (a->format == FMT_APPENDED) {
                int64_t off;
                if (!tag_attr(&t, "offset", val, sizeof val) || parse_count(val, &off))
                    return FAIL(VC_EFORMAT, f->path, "array '%s': appended without a valid offset",
                                array_names[k]);
                a->offset = (uint64_t)off;
            } else {
                /* the content runs to the next tag (VTK may nest an
                 * InformationKey after it) */
                a->text_b = t.self_closing ? t.end : p;
                a->text_e = t.self_closing ? t.end : find_char(p, e, '<');
            }
        } else if (tag_is(&t, "AppendedData")) {
            f->appended_base64 = 1; /* VTK's default encoding */
            if (tag_attr(&t, "encoding", val, sizeof val)) {
                if (!strcmp(val, "raw"))
                    f->appended_base64 = 0;
                else if (strcmp(val, "base64"))
                    return FAIL(VC_EFORMAT, f->path, "AppendedData encoding '%s' is not raw or "
                                "base64", val);
            }
            const char *q = p;
            while (q < e && is_space(*q))
                q++;
            if (q >= e || *q != '_')
                return FAIL(VC_EFORMAT, f->path, "AppendedData without the '_' marker");
            f->app_b = q + 1;
            /* The data ends where "</AppendedData>" starts (searched from
             * the end: raw data may hold any byte). A file cut short has
             * none, and then its data simply runs to the end. */
            f->app_e = e;
            /* Offsets, not pointers before the buffer; r stays in
             * [app_b, e - 15] (no candidate when fewer than 15 bytes
             * follow the marker, e.g. a file cut just after it). */
            size_t data = (size_t)(e - f->app_b);
            if (data >= 15) {
                for (size_t back = 15; back <= data; back++) {
                    const char *r = e - back;
                    if (*r == '<' && !memcmp(r, "</AppendedData>", 15)) {
                        f->app_e = r;
                        break;
                    }
                    if (back > 4096)
                        break; /* only trailing whitespace and </VTKFile> may follow */
                }
            }
            if (f->appended_base64) /* the text ends at the closing tag or any '<' */
                f->app_e = find_char(f->app_b, f->app_e, '<');
            break;
        }
    }
    if (!seen_vtkfile)
        return FAIL(VC_EFORMAT, f->path, "not a VTK XML file (no VTKFile element)");
    if (n_pieces == 0)
        return FAIL(VC_EFORMAT, f->path, "no Piece in the UnstructuredGrid");
    return VC_OK;
}

/* ---- assembling the mesh ------------------------------------------------------ */

typedef struct growing {
    int64_t *v;
    int64_t n, cap;
} growing;

static int grow_push(growing *g, int64_t x)
{
    if (g->n == g->cap) {
        int64_t cap = g->cap ? 2 * g->cap : 1024;
        int64_t *nv = realloc(g->v, sizeof *nv * (size_t)cap);
        if (!nv)
            return -1;
        g->v = nv;
        g->cap = cap;
    }
    g->v[g->n++] = x;
    return 0;
}

void vc_vtu_mesh_free(vc_vtu_mesh *m)
{
    free(m->points);
    free(m->cell_type);
    free(m->cell_file_index);
    free(m->cell_faces);
    free(m->face_offsets);
    free(m->face_vertices);
    free(m->cell_seed_point);
    memset(m, 0, sizeof *m);
}

static int need(const vtu_file *f, int k, vc_error *err)
{
    if (!f->arr[k].present)
        return FAIL(VC_EFORMAT, f->path, "missing the '%s' array", array_names[k]);
    return VC_OK;
}

static int build_mesh(const vtu_file *f, vc_vtu_mesh *m, vc_error *err)
{
    values pts = {0}, conn = {0}, offs = {0}, types = {0};
    values faces = {0}, faceoffs = {0}, fconn = {0}, foffs = {0}, p2f = {0}, poffs = {0};
    growing cf = {0}, fo = {0}, fv = {0};
    int rc;
    const int64_t nc = f->n_cells, np = f->n_points;
    m->n_file_cells = nc;
    m->first_skipped_type = -1;

    if (nc > 0 && ((rc = need(f, ARR_CONN, err)) || (rc = need(f, ARR_OFFSETS, err)) ||
                   (rc = need(f, ARR_TYPES, err))))
        goto out;
    if (np > 0 && (rc = need(f, ARR_POINTS, err)))
        goto out;
    if (np > 0) {
        if (f->arr[ARR_POINTS].ncomp != 3) {
            rc = FAIL(VC_EFORMAT, f->path, "Points have %d components, not 3",
                      f->arr[ARR_POINTS].ncomp);
            goto out;
        }
        if ((rc = read_array(f, ARR_POINTS, 1, &pts, err)))
            goto out;
        if (pts.n % 3 != 0 || pts.n / 3 != np) {
            rc = FAIL(VC_EFORMAT, f->path, "Points hold %" PRId64 " values, expected 3 x %" PRId64,
                      pts.n, np);
            goto out;
        }
        for (int64_t i = 0; i < pts.n; i++)
            if (!isfinite(pts.d[i])) {
                rc = FAIL(VC_EFORMAT, f->path, "point %" PRId64 " has a non-finite coordinate",
                          i / 3);
                goto out;
            }
    }
    if (nc > 0) {
        if ((rc = read_array(f, ARR_CONN, 0, &conn, err)) ||
            (rc = read_array(f, ARR_OFFSETS, 0, &offs, err)) ||
            (rc = read_array(f, ARR_TYPES, 0, &types, err)))
            goto out;
        if (offs.n != nc || types.n != nc) {
            rc = FAIL(VC_EFORMAT, f->path, "%" PRId64 " cells but %" PRId64 " offsets and %" PRId64
                      " types", nc, offs.n, types.n);
            goto out;
        }
    }
    int has_old = f->arr[ARR_FACES].present || f->arr[ARR_FACEOFFSETS].present;
    int has_new = f->arr[ARR_POLY_OFFSETS].present;
    int64_t n_poly = 0;
    for (int64_t c = 0; c < nc; c++)
        n_poly += types.i[c] == VC_VTK_POLYHEDRON;
    if (n_poly > 0 && !has_old && !has_new) {
        rc = FAIL(VC_EFORMAT, f->path, "polyhedral cells but no 'faces' / 'faceoffsets' arrays");
        goto out;
    }
    if (n_poly > 0 && has_new) {
        if ((rc = need(f, ARR_FACE_CONN, err)) || (rc = need(f, ARR_FACE_OFFSETS, err)) ||
            (rc = need(f, ARR_POLY_TO_FACES, err)) ||
            (rc = read_array(f, ARR_FACE_CONN, 0, &fconn, err)) ||
            (rc = read_array(f, ARR_FACE_OFFSETS, 0, &foffs, err)) ||
            (rc = read_array(f, ARR_POLY_TO_FACES, 0, &p2f, err)) ||
            (rc = read_array(f, ARR_POLY_OFFSETS, 0, &poffs, err)))
            goto out;
        if (poffs.n != nc + 1 || foffs.n < 1) {
            rc = FAIL(VC_EFORMAT, f->path, "'polyhedron_offsets' has %" PRId64 " entries, "
                      "expected %" PRId64, poffs.n, nc + 1);
            goto out;
        }
        for (int64_t i = 0; i + 1 < foffs.n; i++)
            if (foffs.i[0] != 0 || foffs.i[i] > foffs.i[i + 1] || foffs.i[foffs.n - 1] != fconn.n) {
                rc = FAIL(VC_EFORMAT, f->path, "'face_offsets' are not increasing from 0 to the "
                          "size of 'face_connectivity'");
                goto out;
            }
    } else if (n_poly > 0) {
        if ((rc = need(f, ARR_FACES, err)) || (rc = need(f, ARR_FACEOFFSETS, err)) ||
            (rc = read_array(f, ARR_FACES, 0, &faces, err)) ||
            (rc = read_array(f, ARR_FACEOFFSETS, 0, &faceoffs, err)))
            goto out;
        if (faceoffs.n != nc) {
            rc = FAIL(VC_EFORMAT, f->path, "'faceoffsets' has %" PRId64 " entries for %" PRId64 " "
                      "cells", faceoffs.n, nc);
            goto out;
        }
    }

    m->n_points = np;
    m->points = pts.d;
    pts.d = NULL;
    m->cell_type = malloc((size_t)(nc ? nc : 1));
    m->cell_file_index = malloc(sizeof(int64_t) * (size_t)(nc ? nc : 1));
    if (!m->cell_type || !m->cell_file_index || grow_push(&cf, 0) || grow_push(&fo, 0)) {
        rc = FAIL(VC_ENOMEM, f->path, "out of memory");
        goto out;
    }
#define PUSH(g, x)                                                   \
    do {                                                             \
        if (grow_push(&(g), (x))) {                                  \
            rc = FAIL(VC_ENOMEM, f->path, "out of memory");      \
            goto out;                                                \
        }                                                            \
    } while (0)
#define CHECK_ID(id, c)                                                                         \
    do {                                                                                        \
        if ((id) < 0 || (id) >= np) {                                                           \
            rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 " uses point %" PRId64               \
                      " out of range (%" PRId64 " points)", (int64_t)(c), (int64_t)(id), np);     \
            goto out;                                                                           \
        }                                                                                       \
    } while (0)

    int64_t conn_start = 0, faces_start = 0;
    for (int64_t c = 0; c < nc; c++) {
        int64_t conn_end = offs.i[c];
        if (conn_end < conn_start || conn_end > conn.n) {
            rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": offset %" PRId64 " out of order or "
                      "past the connectivity (%" PRId64 " ids)", c, conn_end, conn.n);
            goto out;
        }
        int64_t type = types.i[c];
        if (type == VC_VTK_TETRA) {
            if (conn_end - conn_start != 4) {
                rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": a tetrahedron with %" PRId64 " "
                          "points", c, conn_end - conn_start);
                goto out;
            }
            static const int tet_faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
            const int64_t *q = conn.i + conn_start;
            for (int k = 0; k < 4; k++)
                CHECK_ID(q[k], c);
            for (int k = 0; k < 4; k++) {
                for (int j = 0; j < 3; j++)
                    PUSH(fv, q[tet_faces[k][j]]);
                PUSH(fo, fv.n);
            }
        } else if (type == VC_VTK_POLYHEDRON && has_new) {
            int64_t b = poffs.i[c], e = poffs.i[c + 1];
            if (b < 0 || e < b || e > p2f.n) {
                rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": 'polyhedron_offsets' out of "
                          "range", c);
                goto out;
            }
            for (int64_t k = b; k < e; k++) {
                int64_t face = p2f.i[k];
                if (face < 0 || face + 1 >= foffs.n) {
                    rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": face %" PRId64 " out of "
                              "range", c, face);
                    goto out;
                }
                /* A face bounds at most two cells: more uses in all than
                 * twice the face connectivity is a hostile file (its output
                 * would grow as cells x faces). */
                if (fv.n > 2 * fconn.n + 1024 - (foffs.i[face + 1] - foffs.i[face])) {
                    rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": 'polyhedron_to_faces' uses "
                              "the faces more than twice in all", c);
                    goto out;
                }
                for (int64_t j = foffs.i[face]; j < foffs.i[face + 1]; j++) {
                    CHECK_ID(fconn.i[j], c);
                    PUSH(fv, fconn.i[j]);
                }
                PUSH(fo, fv.n);
            }
        } else if (type == VC_VTK_POLYHEDRON) {
            int64_t end = faceoffs.i[c];
            if (end < faces_start || end > faces.n || end == faces_start) {
                rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": faceoffset %" PRId64 " out of "
                          "order or past the 'faces' array (%" PRId64 " values)", c, end, faces.n);
                goto out;
            }
            int64_t k = faces_start, nfaces = faces.i[k++];
            for (int64_t j = 0; j < nfaces; j++) {
                int64_t len = k < end ? faces.i[k++] : -1;
                if (len < 3 || len > end - k) {
                    rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": face %" PRId64 " of its "
                              "record in 'faces' is malformed", c, j);
                    goto out;
                }
                for (int64_t i = 0; i < len; i++) {
                    CHECK_ID(faces.i[k + i], c);
                    PUSH(fv, faces.i[k + i]);
                }
                k += len;
                PUSH(fo, fv.n);
            }
            if (nfaces < 1 || k != end) {
                rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": its record in 'faces' does not "
                          "end at its faceoffset", c);
                goto out;
            }
            faces_start = end;
        } else {
            m->n_skipped++;
            if (m->first_skipped_type < 0)
                m->first_skipped_type = (int)type;
            conn_start = conn_end;
            continue;
        }
        conn_start = conn_end;
        m->cell_type[m->n_cells] = (uint8_t)type;
        m->cell_file_index[m->n_cells] = c;
        m->n_cells++;
        PUSH(cf, fo.n - 1);
    }
#undef PUSH
#undef CHECK_ID
    if (m->n_cells == 0) {
        rc = FAIL(VC_EINPUT, f->path, "no polyhedron or tetrahedron among its %" PRId64 " cells",
                  nc);
        goto out;
    }
    m->cell_faces = cf.v;
    m->n_faces = fo.n - 1;
    m->face_offsets = fo.v;
    m->face_vertices = fv.v;
    cf.v = fo.v = fv.v = NULL;
    if (f->arr[ARR_SEED_POINT].present) {
        values sp = {0};
        if (f->arr[ARR_SEED_POINT].ncomp != 3) {
            rc = FAIL(VC_EFORMAT, f->path, "'seed_point' has %d components, not 3",
                      f->arr[ARR_SEED_POINT].ncomp);
            goto out;
        }
        if ((rc = read_array(f, ARR_SEED_POINT, 1, &sp, err)))
            goto out;
        if (sp.n != 3 * nc) {
            values_free(&sp);
            rc = FAIL(VC_EFORMAT, f->path, "'seed_point' holds %" PRId64 " values, expected 3 x %"
                      PRId64, sp.n, nc);
            goto out;
        }
        m->cell_seed_point = malloc(sizeof(double) * 3 * (size_t)m->n_cells);
        if (!m->cell_seed_point) {
            values_free(&sp);
            rc = FAIL(VC_ENOMEM, f->path, "out of memory");
            goto out;
        }
        for (int64_t c = 0; c < m->n_cells; c++)
            for (int d = 0; d < 3; d++)
                m->cell_seed_point[3 * c + d] = sp.d[3 * m->cell_file_index[c] + d];
        values_free(&sp);
        for (int64_t i = 0; i < 3 * m->n_cells; i++)
            if (!isfinite(m->cell_seed_point[i])) {
                rc = FAIL(VC_EFORMAT, f->path, "cell %" PRId64 ": a non-finite 'seed_point'",
                          m->cell_file_index[i / 3]);
                goto out;
            }
    }
    rc = VC_OK;
out:
    values_free(&pts);
    values_free(&conn);
    values_free(&offs);
    values_free(&types);
    values_free(&faces);
    values_free(&faceoffs);
    values_free(&fconn);
    values_free(&foffs);
    values_free(&p2f);
    values_free(&poffs);
    free(cf.v);
    free(fo.v);
    free(fv.v);
    return rc;
}

int vc_vtu_read(const char *path, vc_vtu_mesh *out, vc_error *err)
{
    memset(out, 0, sizeof *out);
    if (!path)
        return FAIL(VC_EPARAM, NULL, "vc_vtu_read: NULL path");
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return FAIL(VC_EIO, path, "cannot open: %s", strerror(errno));
    vtu_file f;
    memset(&f, 0, sizeof f);
    f.path = path;
    int rc = VC_OK;
    struct stat st;
    if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) {
        rc = FAIL(VC_EIO, path, "%s",
                  fstat(fileno(fp), &st) == 0 && S_ISDIR(st.st_mode) ? "is a directory"
                                                                     : "cannot read: not a regular file");
        goto out;
    }
    if (fseek(fp, 0, SEEK_END) != 0) {
        rc = FAIL(VC_EIO, path, "cannot read: %s", strerror(errno));
        goto out;
    }
    long size = ftell(fp);
    if (size < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        rc = FAIL(VC_EIO, path, "cannot read (not a regular file?)");
        goto out;
    }
    if (size == 0) {
        rc = FAIL(VC_EFORMAT, path, "empty file");
        goto out;
    }
    f.size = (size_t)size;
    f.buf = malloc(f.size);
    if (!f.buf) {
        rc = FAIL(VC_ENOMEM, path, "out of memory");
        goto out;
    }
    if (fread(f.buf, 1, f.size, fp) != f.size) {
        rc = FAIL(VC_EIO, path, "cannot read: %s", ferror(fp) ? strerror(errno) : "short read");
        goto out;
    }
    rc = scan_xml(&f, err);
    if (!rc)
        rc = build_mesh(&f, out, err);
    if (rc)
        vc_vtu_mesh_free(out);
out:
    fclose(fp);
    free(f.buf);
    return rc;
}
