/* Internal to the surface module: the polygon soup the format readers
 * produce, the readers themselves and a small text scanner. */
#ifndef VC_SURFACE_INTERNAL_H
#define VC_SURFACE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "vorocrust/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Vertices and polygons as read: face f has the 0-based vertex indices
 * idx[off[f] .. off[f + 1] - 1]. Indices are not validated by readers. */
typedef struct vc_soup {
    int64_t nv, cap_v;
    double *xyz;
    int64_t nf, cap_f;
    int64_t *off; /* nf + 1 entries once a face exists */
    int64_t ni, cap_i;
    int64_t *idx;
    /* Faces the file announces (header counts), or -1 when unknown; lets
     * the caller see faces a reader skipped. */
    int64_t expected_faces;
    /* How the file numbers its vertices (0 for OFF and PLY, 1 for OBJ):
     * messages quote an index as the file writes it. */
    int index_base;
    /* Named groups (vc_soup_set_group): per face its group (faces before
     * the first group statement: "surface"). */
    int32_t *face_group;
    int64_t cap_g;
    int32_t n_groups, cap_names, cur_group;
    char (*group_name)[64];
} vc_soup;

int vc_soup_add_vertex(vc_soup *s, double x, double y, double z);
/* Appends a face of n indices. */
int vc_soup_add_face(vc_soup *s, const int64_t *v, int64_t n);
/* The faces added from now on belong to the group of this name (the first
 * len bytes of name, cut to 63; an empty name is "surface"). */
int vc_soup_set_group(vc_soup *s, const char *name, size_t len);
void vc_soup_free(vc_soup *s);

/* Readers: name is used in messages; buf holds the whole file and has a
 * NUL byte at buf[len]. Return 0 or a VC_E* code with err set. */
int vc_read_obj(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err);
int vc_read_off(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err);
int vc_read_stl(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err);
int vc_read_ply(const char *name, const char *buf, size_t len, vc_soup *s, vc_error *err);

/* A reader returns this code (with err unset) for a variant of its format
 * it leaves to OpenMesh, e.g. binary OFF. */
#define VC_SURFACE_DEFER_TO_OPENMESH (-100)

/* Reads any format OpenMesh knows through OpenMesh's IO manager
 * (openmesh_reader.cpp). Coordinates come through OpenMesh's float path.
 * name (the path, escaped) is used in messages. */
int vc_openmesh_read(const char *path, const char *name, vc_soup *s, vc_error *err);

/* --- Text scanning over a NUL-terminated buffer. --- */
typedef struct vc_scan {
    const char *p, *end;
    int64_t line; /* 1-based line of p */
} vc_scan;

static inline int vc_scan_is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/* Whether p starts a line continuation: a backslash that ends its line
 * (OBJ writers break long face lines so; before a CR of a CRLF too). */
static inline int vc_scan_continues(const vc_scan *sc, const char *p)
{
    return p < sc->end && *p == '\\' &&
           ((p + 1 < sc->end && p[1] == '\n') || (p + 2 < sc->end && p[1] == '\r' && p[2] == '\n'));
}

/* Skips blanks on the current line, and line continuations. */
static inline void vc_scan_blanks(vc_scan *sc)
{
    for (;;) {
        while (sc->p < sc->end && vc_scan_is_blank(*sc->p))
            sc->p++;
        if (!vc_scan_continues(sc, sc->p))
            return;
        sc->p += sc->p[1] == '\n' ? 2 : 3;
        sc->line++;
    }
}

/* Moves to the start of the next line. */
static inline void vc_scan_next_line(vc_scan *sc)
{
    while (sc->p < sc->end && *sc->p != '\n')
        sc->p++;
    if (sc->p < sc->end) {
        sc->p++;
        sc->line++;
    }
}

/* Whether the rest of the current line is blank or a '#' comment. */
static inline int vc_scan_at_eol(vc_scan *sc)
{
    vc_scan_blanks(sc);
    return sc->p >= sc->end || *sc->p == '\n' || *sc->p == '#';
}

/* Skips whitespace, newlines and '#' comments (when comments is set). */
void vc_scan_space(vc_scan *sc, int comments);
/* Parses a number on the current line (after blanks); the number must end
 * at a blank, a line end, a '#', a line continuation or the end of the buffer ("2.7" is not an
 * integer, "3abc" not a number). Return 1 on success. */
int vc_scan_double(vc_scan *sc, double *v);
int vc_scan_int(vc_scan *sc, int64_t *v);
/* Copies the next blank-delimited word of the current line (truncated to
 * cap - 1 characters); returns its length, 0 at end of line. */
size_t vc_scan_word(vc_scan *sc, char *w, size_t cap);
/* Whether a number may end at p (blank, line end, '#', continuation or end). */
static inline int vc_scan_is_end(const vc_scan *sc, const char *p)
{
    return p >= sc->end || vc_scan_is_blank(*p) || *p == '\n' || *p == '#' || vc_scan_continues(sc, p);
}

/* Little-endian fields of the binary formats (STL, binary OFF). */
static inline uint32_t vc_le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}
static inline double vc_le_float(const unsigned char *b)
{
    uint32_t u = vc_le32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return (double)f;
}

#ifdef __cplusplus
}
#endif
/* vc_soup_set_group with the rest of the scanner's line (blanks trimmed)
 * as the name; the scanner does not move. */
int vc_soup_set_group_rest(vc_soup *s, vc_scan *sc);

/* Is the triangle a, b, c of xyz of zero area by vc_surface_check's test,
 * |cross| <= VC_SOLID_ZERO_AREA * (longest edge)^2 (unscaled: for the
 * repairs, which run on surfaces the checks accepted)? */
int vc_triangle_zero_area(const double *xyz, int64_t a, int64_t b, int64_t c);

#endif
