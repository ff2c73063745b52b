/* OpenFOAM polyMesh writer: CASE_DIR/constant/polyMesh/{points, faces,
 * owner, neighbour, boundary} in OpenFOAM's ASCII format, and a minimal
 * CASE_DIR/system/controlDict when the case has none (every OpenFOAM
 * utility, checkMesh included, reads it).
 *
 * Face order (what OpenFOAM requires): the interior faces first, in
 * upper-triangular order (sorted by owner, then neighbour, owner <
 * neighbour), each oriented from its owner to its neighbour; then the
 * boundary faces grouped by patch, each pointing out of the domain.
 * vc_polymesh already stores its interior faces that way; the writer checks
 * it and only sorts or flips faces when a mesh does not.
 *
 * Patches come from vc_polymesh_boundary_patches (every writer's): a
 * boundary face against a non-kept seed belongs to "surface", a face on the
 * clipping box to the wall's patch ("xmin" ... "zmax"), split by region
 * when the cells have several labels; all of type "patch". Within a patch,
 * faces keep the mesh's order (by owner).
 *
 * Atomicity: a new case is assembled in a sibling directory
 * "CASE_DIR.tmp.XXXXXX" and renamed to CASE_DIR at the end. Into an
 * existing case, the new polyMesh is assembled in
 * "constant/polyMesh.tmp.XXXXXX" and swapped with the old one (which is
 * then removed with its contents); a missing system/controlDict is added
 * through a temporary file. A failure removes whatever was created; so
 * does a signal in a program that tracks the temporary files (io/tmpfile.h:
 * the directories this run made, and the old polyMesh put back).
 *
 * Numbers are formatted by hand (17 significant digits for coordinates,
 * enough to read back the same doubles; printf is several times slower),
 * blocks of entries in parallel (OpenMP), written in order. */
#include "vorocrust/io.h"
#include "io/tmpfile.h"

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#define FOAM_BUF ((size_t)1 << 20)
#define FOAM_NUM_MAX 32 /* longest formatted number, with separator */

/* ---- numbers ------------------------------------------------------------ */

static char *foam_fmt_u64(char *p, uint64_t v)
{
    char tmp[24];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (n)
        *p++ = tmp[--n];
    return p;
}

static char *foam_fmt_i64(char *p, int64_t v)
{
    if (v < 0) {
        *p++ = '-';
        return foam_fmt_u64(p, (uint64_t)0 - (uint64_t)v);
    }
    return foam_fmt_u64(p, (uint64_t)v);
}

#if LDBL_MANT_DIG >= 64
/* 10^n for 0 <= n <= 27: exact in a 64-bit-mantissa long double
 * (5^27 < 2^64). */
static const long double foam_pow10[28] = {
    1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,  1e8L,  1e9L,
    1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L,
    1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};

/* v * 10^n, |n| <= 54: at most two roundings of relative size 2^-64. */
static long double foam_scale10(long double v, int n)
{
    int a = n < 0 ? -n : n;
    long double f = a > 27 ? foam_pow10[27] * foam_pow10[a - 27] : foam_pow10[a];
    return n < 0 ? v / f : v * f;
}
#endif

/* x with 17 significant digits, the text printf's "%.17g" gives (fixed
 * notation for exponents -4 .. 16, else d.ddde+XX; trailing zeros dropped),
 * which reads back as x. With a 64-bit long double mantissa, x * 10^(16-k)
 * is computed with two roundings at most (relative 2^-64 each, 0.01 units
 * of the 17th digit), and rounded to an integer here unless it is that
 * close to a tie; otherwise, for near ties and for magnitudes beyond 1e+-30,
 * printf. About 5x faster than printf. */
static char *foam_fmt_double(char *p, double x)
{
    if (x == 0) {
        *p++ = '0';
        return p;
    }
#if LDBL_MANT_DIG >= 64
    double ax = fabs(x);
    if (isfinite(x) && ax > 1e-30 && ax < 1e30) { /* |16 - k| <= 48 */
        int e2;
        (void)frexp(ax, &e2);
        int k = (int)floor((e2 - 1) * 0.30102999566398120);
        long double s = foam_scale10((long double)ax, 16 - k);
        if (s < 1e16L) {
            k--;
            s = foam_scale10((long double)ax, 16 - k);
        } else if (s >= 1e17L) {
            k++;
            s = foam_scale10((long double)ax, 16 - k);
        }
        /* s is within 0.01 of the exact x * 10^(16-k); when that leaves the
         * rounding in doubt (a near tie, about 2% of numbers), printf
         * decides, so the text is always the correctly rounded one. */
        long double frac = s - floorl(s);
        if (frac > 0.48L && frac < 0.52L)
            return p + snprintf(p, FOAM_NUM_MAX, "%.17g", x);
        uint64_t d = (uint64_t)(s + 0.5L);
        if (d >= 100000000000000000ULL) {
            d /= 10;
            k++;
        }
        char dig[17];
        for (int i = 16; i >= 0; i--) {
            dig[i] = (char)('0' + d % 10);
            d /= 10;
        }
        int nd = 17;
        while (nd > 1 && dig[nd - 1] == '0')
            nd--;
        if (x < 0)
            *p++ = '-';
        if (k >= -4 && k < 17) {
            if (k >= 0) {
                for (int i = 0; i <= k; i++)
                    *p++ = i < nd ? dig[i] : '0';
                if (nd > k + 1) {
                    *p++ = '.';
                    for (int i = k + 1; i < nd; i++)
                        *p++ = dig[i];
                }
            } else {
                *p++ = '0';
                *p++ = '.';
                for (int i = 0; i < -k - 1; i++)
                    *p++ = '0';
                for (int i = 0; i < nd; i++)
                    *p++ = dig[i];
            }
        } else {
            *p++ = dig[0];
            if (nd > 1) {
                *p++ = '.';
                for (int i = 1; i < nd; i++)
                    *p++ = dig[i];
            }
            *p++ = 'e';
            *p++ = k < 0 ? '-' : '+';
            int ak = k < 0 ? -k : k;
            if (ak < 10)
                *p++ = '0';
            p = foam_fmt_u64(p, (uint64_t)ak);
        }
        return p;
    }
#endif
    return p + snprintf(p, FOAM_NUM_MAX, "%.17g", x);
}

/* Exposed for the unit test through a declaration there (not in io.h). */
size_t vc_foam_format_double(char *out, double x);
size_t vc_foam_format_double(char *out, double x)
{
    char *e = foam_fmt_double(out, x);
    *e = 0;
    return (size_t)(e - out);
}

/* ---- buffered output ---------------------------------------------------- */

typedef struct foam_out {
    FILE *fp;
    char *buf;
    size_t len, cap;
    int err_no; /* first write error */
} foam_out;

static void foam_flush(foam_out *o)
{
    if (o->len && !o->err_no && fwrite(o->buf, 1, o->len, o->fp) != o->len)
        o->err_no = errno ? errno : EIO;
    o->len = 0;
}

/* Room for need more bytes at o->buf + o->len; 0 on success. */
static int foam_reserve(foam_out *o, size_t need)
{
    if (o->len + need <= o->cap)
        return 0;
    foam_flush(o);
    if (need > o->cap) {
        char *b = realloc(o->buf, need);
        if (!b)
            return -1;
        o->buf = b;
        o->cap = need;
    }
    return 0;
}

static void foam_puts(foam_out *o, const char *s)
{
    size_t n = strlen(s);
    if (foam_reserve(o, n) == 0) {
        memcpy(o->buf + o->len, s, n);
        o->len += n;
    } else if (!o->err_no) {
        o->err_no = ENOMEM;
    }
}

/* The FoamFile header. note may be NULL. */
static void foam_header(foam_out *o, const char *cls, const char *location, const char *object,
                        const char *note)
{
    char h[1024];
    snprintf(h, sizeof h,
             "/* OpenFOAM mesh file written by vorocrust (conforming Voronoi mesh) */\n"
             "FoamFile\n"
             "{\n"
             "    version     2.0;\n"
             "    format      ascii;\n"
             "    class       %s;\n"
             "%s%s%s"
             "    location    \"%s\";\n"
             "    object      %s;\n"
             "}\n\n",
             cls, note ? "    note        \"" : "", note ? note : "", note ? "\";\n" : "",
             location, object);
    foam_puts(o, h);
}

/* ---- the mesh as OpenFOAM sees it ---------------------------------------- */

typedef struct foam_plan {
    int64_t n_points;   /* used points */
    int64_t *point_map; /* old index -> written index, or NULL if all used */
    int64_t *point_of;  /* written index -> old index, or NULL */
    int64_t n_faces, n_internal;
    int64_t *order;      /* written face -> mesh face */
    unsigned char *flip; /* written interior face is reversed (owner/neighbour swapped) */
    /* The patches (vc_polymesh_boundary_patches), where each starts, its
     * type and whether it names its input group (inGroups). */
    vc_boundary_patches patches;
    int64_t *patch_start;
    const char **patch_type;
    const char **patch_base; /* its input group, or its name without "regionN_" */
    /* With several regions (patches.n_labels > 1): cell zone k holds the
     * cells of label patches.label_value[k] (cells zone_cell[
     * zone_cell_start[k] ..]), and face zone j the interior faces between
     * two regions (written indices zone_face[zone_face_start[j] ..], flipped
     * where they point from the higher region to the lower). */
    int64_t *zone_cell, *zone_cell_start;
    int n_face_zones;
    int32_t *face_zone_pair;  /* 2 per face zone: the lower and the higher label */
    int64_t *zone_face, *zone_face_start;
    unsigned char *zone_flip;
} foam_plan;

static void foam_plan_free(foam_plan *pl)
{
    free(pl->point_map);
    free(pl->point_of);
    free(pl->order);
    free(pl->flip);
    vc_boundary_patches_free(&pl->patches);
    free(pl->patch_start);
    free(pl->patch_type);
    free(pl->patch_base);
    free(pl->zone_cell);
    free(pl->zone_cell_start);
    free(pl->face_zone_pair);
    free(pl->zone_face);
    free(pl->zone_face_start);
    free(pl->zone_flip);
    memset(pl, 0, sizeof *pl);
}

static void foam_face_cells(const vc_polymesh *m, const unsigned char *flip, int64_t f,
                            int64_t *own, int64_t *nei)
{
    int64_t a = m->face_owner[f], b = m->face_neighbour[f];
    if (flip[f]) {
        *own = b;
        *nei = a;
    } else {
        *own = a;
        *nei = b;
    }
}

/* An interior face with its owner and neighbour as written: sorting these
 * needs no state outside the comparator (file-scope pointers for it made
 * two meshes written at once race). */
typedef struct foam_face_key {
    int64_t own, nei, f;
} foam_face_key;

static int foam_cmp_interior(const void *pa, const void *pb)
{
    const foam_face_key *a = pa, *b = pb;
    if (a->own != b->own)
        return a->own < b->own ? -1 : 1;
    if (a->nei != b->nei)
        return a->nei < b->nei ? -1 : 1;
    return (a->f > b->f) - (a->f < b->f);
}

typedef struct foam_zone_face {
    int32_t lo, hi;  /* label ranks */
    int64_t written; /* written face index */
    unsigned char flip;
} foam_zone_face;

static int foam_cmp_zone_face(const void *a, const void *b)
{
    const foam_zone_face *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return (x->written > y->written) - (x->written < y->written);
}

/* The cell zones (one per region) and face zones (one per pair of regions
 * that share faces), from the written face order. */
static int foam_plan_zones(const vc_polymesh *m, foam_plan *pl)
{
    const int nl = pl->patches.n_labels;
    pl->zone_cell = malloc(sizeof(int64_t) * (size_t)(m->n_cells + 1));
    pl->zone_cell_start = calloc((size_t)nl + 1, sizeof(int64_t));
    int64_t nz = 0;
    for (int64_t w = 0; w < pl->n_internal; w++) {
        const int64_t f = pl->order[w];
        nz += m->cell_region[m->face_owner[f]] != m->cell_region[m->face_neighbour[f]];
    }
    foam_zone_face *zf = malloc(sizeof(foam_zone_face) * (size_t)(nz + 1));
    if (!pl->zone_cell || !pl->zone_cell_start || !zf) {
        free(zf);
        return -1;
    }
    int *rank = malloc(sizeof(int) * (size_t)(m->n_cells + 1));
    if (!rank) {
        free(zf);
        return -1;
    }
    for (int64_t c = 0; c < m->n_cells; c++) {
        rank[c] = vc_boundary_patches_label_rank(&pl->patches, m->cell_region[c]);
        pl->zone_cell_start[rank[c] + 1]++;
    }
    for (int k = 0; k < nl; k++)
        pl->zone_cell_start[k + 1] += pl->zone_cell_start[k];
    int64_t *fill = malloc(sizeof(int64_t) * (size_t)(nl + 1));
    if (!fill) {
        free(zf);
        free(rank);
        return -1;
    }
    memcpy(fill, pl->zone_cell_start, sizeof(int64_t) * (size_t)nl);
    for (int64_t c = 0; c < m->n_cells; c++)
        pl->zone_cell[fill[rank[c]]++] = c;
    free(fill);
    nz = 0;
    for (int64_t w = 0; w < pl->n_internal; w++) {
        const int64_t f = pl->order[w];
        int64_t own, nei;
        foam_face_cells(m, pl->flip, f, &own, &nei);
        const int ro = rank[own], rn = rank[nei];
        if (ro == rn)
            continue;
        /* the zone points from the lower region to the higher */
        zf[nz++] = (foam_zone_face){ro < rn ? ro : rn, ro < rn ? rn : ro, w, (unsigned char)(ro > rn)};
    }
    free(rank);
    qsort(zf, (size_t)nz, sizeof(foam_zone_face), foam_cmp_zone_face);
    int64_t npairs = 0;
    for (int64_t i = 0; i < nz; i++)
        npairs += i == 0 || zf[i].lo != zf[i - 1].lo || zf[i].hi != zf[i - 1].hi;
    pl->face_zone_pair = malloc(sizeof(int32_t) * 2 * (size_t)(npairs + 1));
    pl->zone_face_start = malloc(sizeof(int64_t) * (size_t)(npairs + 1));
    pl->zone_face = malloc(sizeof(int64_t) * (size_t)(nz + 1));
    pl->zone_flip = malloc((size_t)nz + 1);
    if (!pl->face_zone_pair || !pl->zone_face_start || !pl->zone_face || !pl->zone_flip) {
        free(zf);
        return -1;
    }
    int j = -1;
    for (int64_t i = 0; i < nz; i++) {
        if (i == 0 || zf[i].lo != zf[i - 1].lo || zf[i].hi != zf[i - 1].hi) {
            j++;
            pl->face_zone_pair[2 * j] = pl->patches.label_value[zf[i].lo];
            pl->face_zone_pair[2 * j + 1] = pl->patches.label_value[zf[i].hi];
            pl->zone_face_start[j] = i;
        }
        pl->zone_face[i] = zf[i].written;
        pl->zone_flip[i] = zf[i].flip;
    }
    pl->n_face_zones = j + 1;
    pl->zone_face_start[j + 1] = nz;
    free(zf);
    return 0;
}

/* The base name of patch k: its input group, or the patch name without
 * its "regionN_" prefix. */
static const char *foam_patch_base(const vc_polymesh *m, const vc_boundary_patches *bp, int k)
{
    if (bp->group[k] >= 0)
        return m->group_name[bp->group[k]];
    if (bp->n_labels > 1 && strchr(bp->name[k], '_'))
        return strchr(bp->name[k], '_') + 1;
    return bp->name[k];
}

static int foam_plan_build(const vc_polymesh *m, const char *path, const vc_foam_patch_type *types,
                           int n_types, foam_plan *pl, vc_error *err)
{
    memset(pl, 0, sizeof *pl);
    if (m->n_points < 0 || m->n_faces < 0 || m->n_cells <= 0 || m->n_interior_faces < 0 ||
        m->n_interior_faces > m->n_faces)
        return vc_error_set(err, VC_EINPUT, "%s: bad mesh counts (%" PRId64 " points, %" PRId64
                            " faces, %" PRId64 " interior, %" PRId64 " cells)",
                            path, m->n_points, m->n_faces, m->n_interior_faces, m->n_cells);
    if (!m->points || !m->face_offsets || !m->face_vertices || !m->face_owner ||
        (m->n_interior_faces > 0 && !m->face_neighbour))
        return vc_error_set(err, VC_EINPUT, "%s: mesh lacks points or faces", path);
    int64_t nf = m->n_faces, ni = m->n_interior_faces;
    pl->n_faces = nf;
    pl->n_internal = ni;
    pl->order = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *pl->order);
    pl->flip = calloc((size_t)(nf > 0 ? nf : 1), 1);
    unsigned char *used = calloc((size_t)(m->n_points > 0 ? m->n_points : 1), 1);
    if (!pl->order || !pl->flip || !used) {
        free(used);
        foam_plan_free(pl);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    int rc = VC_OK;
    for (int64_t f = 0; f < nf && rc == VC_OK; f++) {
        int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1];
        int64_t own = m->face_owner[f], nei = f < ni ? m->face_neighbour[f] : -1;
        if (e - b < 3 || b < 0)
            rc = vc_error_set(err, VC_EINPUT, "%s: face %" PRId64 " has %" PRId64 " vertices",
                              path, f, e - b);
        else if (own < 0 || own >= m->n_cells || (f < ni && (nei < 0 || nei >= m->n_cells)))
            rc = vc_error_set(err, VC_EINPUT,
                              "%s: face %" PRId64 " has cells %" PRId64 ", %" PRId64
                              " (of %" PRId64 ")",
                              path, f, own, nei, m->n_cells);
        else if (f < ni && own == nei)
            rc = vc_error_set(err, VC_EINPUT, "%s: interior face %" PRId64
                              " has cell %" PRId64 " on both sides", path, f, own);
        for (int64_t i = b; i < e && rc == VC_OK; i++) {
            int64_t v = m->face_vertices[i];
            if (v < 0 || v >= m->n_points)
                rc = vc_error_set(err, VC_EINPUT, "%s: face %" PRId64 " has vertex %" PRId64
                                  " (of %" PRId64 ")", path, f, v, m->n_points);
            else
                used[v] = 1;
        }
    }
    if (rc == VC_OK) {
        int64_t bad = -1;
        const int prc = vc_polymesh_boundary_patches(m, &pl->patches, &bad);
        if (prc == -1)
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
        else if (prc == -2)
            rc = vc_error_set(err, VC_EINPUT, "%s: boundary face %" PRId64
                              " has an unknown wall code %" PRId64, path, bad,
                              m->face_other_seed[bad]);
    }
    for (int64_t i = 0; i < m->n_points && rc == VC_OK; i++)
        if (!isfinite(m->points[3 * i]) || !isfinite(m->points[3 * i + 1]) ||
            !isfinite(m->points[3 * i + 2]))
            rc = vc_error_set(err, VC_EINPUT, "%s: point %" PRId64 " is not finite", path, i);
    if (rc != VC_OK) {
        free(used);
        foam_plan_free(pl);
        return rc;
    }

    /* Points: OpenFOAM counts unused points as an error; drop them. */
    int64_t n_used = 0;
    for (int64_t i = 0; i < m->n_points; i++)
        n_used += used[i];
    pl->n_points = n_used;
    if (n_used < m->n_points) {
        pl->point_map = malloc((size_t)m->n_points * sizeof *pl->point_map);
        pl->point_of = malloc((size_t)(n_used > 0 ? n_used : 1) * sizeof *pl->point_of);
        if (!pl->point_map || !pl->point_of) {
            free(used);
            foam_plan_free(pl);
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
        }
        int64_t k = 0;
        for (int64_t i = 0; i < m->n_points; i++) {
            pl->point_map[i] = used[i] ? k : -1;
            if (used[i])
                pl->point_of[k++] = i;
        }
    }
    free(used);

    /* Interior faces: owner < neighbour, upper-triangular order. */
    int sorted = 1;
    int64_t po = -1, pn = -1;
    for (int64_t f = 0; f < ni; f++) {
        pl->flip[f] = m->face_owner[f] > m->face_neighbour[f];
        pl->order[f] = f;
        int64_t o, n;
        foam_face_cells(m, pl->flip, f, &o, &n);
        if (o < po || (o == po && n <= pn))
            sorted = 0; /* equal pairs (two faces between two cells) also land here */
        po = o;
        pn = n;
    }
    if (!sorted) {
        foam_face_key *key = malloc(sizeof *key * (size_t)(ni ? ni : 1));
        if (!key)
            rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
        for (int64_t f = 0; key && f < ni; f++) {
            foam_face_cells(m, pl->flip, f, &key[f].own, &key[f].nei);
            key[f].f = f;
        }
        if (key)
            qsort(key, (size_t)ni, sizeof *key, foam_cmp_interior);
        for (int64_t f = 0; key && f < ni; f++)
            pl->order[f] = key[f].f;
        free(key);
        for (int64_t f = 1; rc == VC_OK && f < ni; f++) {
            int64_t oa, na, ob, nb;
            foam_face_cells(m, pl->flip, pl->order[f - 1], &oa, &na);
            foam_face_cells(m, pl->flip, pl->order[f], &ob, &nb);
            if (oa == ob && na == nb) {
                rc = vc_error_set(err, VC_EINPUT, "%s: cells %" PRId64 " and %" PRId64
                                  " share more than one face", path, oa, na);
                break;
            }
        }
    }

    /* Boundary faces: grouped by patch, mesh order within a patch. */
    const vc_boundary_patches *bp = &pl->patches;
    int64_t *next = malloc(sizeof(int64_t) * (size_t)(bp->n_patches + 1));
    pl->patch_start = malloc(sizeof(int64_t) * (size_t)(bp->n_patches + 1));
    if (rc == VC_OK && (!next || !pl->patch_start))
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    if (rc == VC_OK) {
        int64_t start = ni;
        for (int k = 0; k < bp->n_patches; k++) {
            next[k] = pl->patch_start[k] = start;
            start += bp->size[k];
        }
        for (int64_t f = ni; f < nf; f++)
            pl->order[next[bp->face_patch[f - ni]]++] = f;
    }
    free(next);
    if (rc == VC_OK && bp->n_labels > 1 && foam_plan_zones(m, pl) != 0)
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    /* Patch types: the caller's, by patch name or input group; else a
     * surface without named groups is a wall, anything else a patch. */
    pl->patch_type = malloc(sizeof(char *) * (size_t)(bp->n_patches + 1));
    pl->patch_base = malloc(sizeof(char *) * (size_t)(bp->n_patches + 1));
    if (rc == VC_OK && (!pl->patch_type || !pl->patch_base))
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    for (int k = 0; rc == VC_OK && k < bp->n_patches; k++) {
        const char *base = pl->patch_base[k] = foam_patch_base(m, bp, k);
        pl->patch_type[k] = !m->face_group && !strcmp(base, "surface") ? "wall" : "patch";
        for (int i = 0; i < n_types; i++)
            if (!strcmp(types[i].name, bp->name[k]) || !strcmp(types[i].name, base))
                pl->patch_type[k] = types[i].type;
    }
    if (rc != VC_OK)
        foam_plan_free(pl);
    return rc;
}

/* ---- the files ------------------------------------------------------------ */

/* The list entries, one per line; each formatter writes entry i at p and
 * returns the end, within foam_item_bound() bytes. */
typedef enum { FOAM_ITEM_POINT, FOAM_ITEM_FACE, FOAM_ITEM_OWNER, FOAM_ITEM_NEIGHBOUR } foam_item;

static size_t foam_item_bound(const vc_polymesh *m, const foam_plan *pl, foam_item kind,
                              int64_t i)
{
    if (kind == FOAM_ITEM_POINT)
        return 3 * FOAM_NUM_MAX + 4;
    if (kind == FOAM_ITEM_FACE) {
        int64_t f = pl->order[i];
        return (size_t)(m->face_offsets[f + 1] - m->face_offsets[f] + 1) * 21 + 4;
    }
    return 22;
}

static char *foam_item_format(char *p, const vc_polymesh *m, const foam_plan *pl,
                              foam_item kind, int64_t i)
{
    if (kind == FOAM_ITEM_POINT) {
        const double *x = m->points + 3 * (pl->point_of ? pl->point_of[i] : i);
        *p++ = '(';
        p = foam_fmt_double(p, x[0]);
        *p++ = ' ';
        p = foam_fmt_double(p, x[1]);
        *p++ = ' ';
        p = foam_fmt_double(p, x[2]);
        *p++ = ')';
    } else if (kind == FOAM_ITEM_FACE) {
        int64_t f = pl->order[i];
        int64_t b = m->face_offsets[f], e = m->face_offsets[f + 1], n = e - b;
        p = foam_fmt_i64(p, n);
        *p++ = '(';
        for (int64_t j = 0; j < n; j++) {
            /* A flipped face is written in reverse, starting at the same vertex. */
            int64_t v = m->face_vertices[pl->flip[f] ? (j == 0 ? b : e - j) : b + j];
            if (pl->point_map)
                v = pl->point_map[v];
            if (j)
                *p++ = ' ';
            p = foam_fmt_i64(p, v);
        }
        *p++ = ')';
    } else {
        int64_t f = pl->order[i], c;
        if (i < pl->n_internal) {
            int64_t own, nei;
            foam_face_cells(m, pl->flip, f, &own, &nei);
            c = kind == FOAM_ITEM_OWNER ? own : nei;
        } else {
            c = m->face_owner[f];
        }
        p = foam_fmt_i64(p, c);
    }
    *p++ = '\n';
    return p;
}

#define FOAM_BLOCK 8192 /* entries formatted by one thread at a time */
#define FOAM_BATCH 16   /* blocks formatted in parallel, then written in order */

/* "n\n(\n", the n entries, ")\n". Blocks of entries are formatted in
 * parallel into their own buffers and written in order: the text does not
 * depend on the number of threads. */
static void foam_write_list(foam_out *o, const vc_polymesh *m, const foam_plan *pl,
                            foam_item kind, int64_t n)
{
    char head[32];
    char *e = foam_fmt_i64(head, n);
    memcpy(e, "\n(\n", 4);
    foam_puts(o, head);
    char *bufs[FOAM_BATCH] = {0};
    size_t caps[FOAM_BATCH] = {0}, lens[FOAM_BATCH] = {0};
    int64_t nblocks = (n + FOAM_BLOCK - 1) / FOAM_BLOCK;
    for (int64_t b0 = 0; b0 < nblocks && !o->err_no; b0 += FOAM_BATCH) {
        int nb = (int)(nblocks - b0 < FOAM_BATCH ? nblocks - b0 : FOAM_BATCH);
        int nomem = 0;
#pragma omp parallel for schedule(dynamic) if (nb > 1) reduction(| : nomem)
        for (int j = 0; j < nb; j++) {
            int64_t lo = (b0 + j) * FOAM_BLOCK, hi = lo + FOAM_BLOCK < n ? lo + FOAM_BLOCK : n;
            size_t need = 0;
            for (int64_t i = lo; i < hi; i++)
                need += foam_item_bound(m, pl, kind, i);
            if (need > caps[j]) {
                char *nbuf = realloc(bufs[j], need);
                if (!nbuf) {
                    nomem = 1;
                    lens[j] = 0;
                    continue;
                }
                bufs[j] = nbuf;
                caps[j] = need;
            }
            char *p = bufs[j];
            for (int64_t i = lo; i < hi; i++)
                p = foam_item_format(p, m, pl, kind, i);
            lens[j] = (size_t)(p - bufs[j]);
        }
        if (nomem) {
            o->err_no = ENOMEM;
            break;
        }
        foam_flush(o);
        for (int j = 0; j < nb && !o->err_no; j++)
            if (fwrite(bufs[j], 1, lens[j], o->fp) != lens[j])
                o->err_no = errno ? errno : EIO;
    }
    for (int j = 0; j < FOAM_BATCH; j++)
        free(bufs[j]);
    foam_puts(o, ")\n");
}

static void foam_write_points(foam_out *o, const vc_polymesh *m, const foam_plan *pl)
{
    foam_header(o, "vectorField", "constant/polyMesh", "points", NULL);
    foam_write_list(o, m, pl, FOAM_ITEM_POINT, pl->n_points);
}

static void foam_write_faces(foam_out *o, const vc_polymesh *m, const foam_plan *pl)
{
    foam_header(o, "faceList", "constant/polyMesh", "faces", NULL);
    foam_write_list(o, m, pl, FOAM_ITEM_FACE, pl->n_faces);
}

/* owner (every face) or neighbour (interior faces). */
static void foam_write_cells(foam_out *o, const vc_polymesh *m, const foam_plan *pl, int owner)
{
    char note[256];
    snprintf(note, sizeof note,
             "nPoints:%" PRId64 "  nCells:%" PRId64 "  nFaces:%" PRId64
             "  nInternalFaces:%" PRId64,
             pl->n_points, m->n_cells, pl->n_faces, pl->n_internal);
    foam_header(o, "labelList", "constant/polyMesh", owner ? "owner" : "neighbour", note);
    foam_write_list(o, m, pl, owner ? FOAM_ITEM_OWNER : FOAM_ITEM_NEIGHBOUR,
                    owner ? pl->n_faces : pl->n_internal);
}

static void foam_write_boundary(foam_out *o, const foam_plan *pl)
{
    const vc_boundary_patches *bp = &pl->patches;
    foam_header(o, "polyBoundaryMesh", "constant/polyMesh", "boundary", NULL);
    char line[512];
    snprintf(line, sizeof line, "%d\n(\n", pl->patches.n_patches);
    foam_puts(o, line);
    for (int k = 0; k < bp->n_patches; k++) {
        /* with several regions, a patch split off an input group names it */
        char groups[128] = "";
        if (bp->n_labels > 1)
            snprintf(groups, sizeof groups, "        inGroups        List<word> 1(%.63s);\n",
                     pl->patch_base[k]);
        snprintf(line, sizeof line,
                 "    %s\n    {\n        type            %s;\n%s"
                 "        nFaces          %" PRId64 ";\n        startFace       %" PRId64
                 ";\n    }\n",
                 bp->name[k], pl->patch_type[k], groups, bp->size[k], pl->patch_start[k]);
        foam_puts(o, line);
    }
    foam_puts(o, ")\n");
}

/* A labelList (or with flips, a boolList) in OpenFOAM's List<> syntax. */
static void foam_put_list(foam_out *o, const char *name, const char *type, const int64_t *v,
                          const unsigned char *flags, int64_t n)
{
    char line[96];
    snprintf(line, sizeof line, "        %s List<%s> %" PRId64 "\n(\n", name, type, n);
    foam_puts(o, line);
    for (int64_t i = 0; i < n && !o->err_no; i++) {
        if (foam_reserve(o, FOAM_NUM_MAX + 2)) {
            o->err_no = ENOMEM;
            break;
        }
        char *e = v ? foam_fmt_i64(o->buf + o->len, v[i]) : o->buf + o->len;
        if (!v)
            *e++ = flags[i] ? '1' : '0';
        *e++ = '\n';
        o->len = (size_t)(e - o->buf);
    }
    foam_puts(o, ")\n        ;\n");
}

/* cellZones: "regionN" for the cells of label N. */
static void foam_write_cell_zones(foam_out *o, const foam_plan *pl)
{
    foam_header(o, "regIOobject", "constant/polyMesh", "cellZones", NULL);
    char line[128];
    snprintf(line, sizeof line, "%d\n(\n", pl->patches.n_labels);
    foam_puts(o, line);
    for (int k = 0; k < pl->patches.n_labels; k++) {
        snprintf(line, sizeof line, "    region%d\n    {\n        type cellZone;\n",
                 (int)pl->patches.label_value[k]);
        foam_puts(o, line);
        foam_put_list(o, "cellLabels", "label", pl->zone_cell + pl->zone_cell_start[k], NULL,
                      pl->zone_cell_start[k + 1] - pl->zone_cell_start[k]);
        foam_puts(o, "    }\n");
    }
    foam_puts(o, ")\n");
}

/* faceZones: "regionA_to_regionB" for the faces between labels A < B,
 * oriented from A to B (flipMap 1 where the face points the other way). */
static void foam_write_face_zones(foam_out *o, const foam_plan *pl)
{
    foam_header(o, "regIOobject", "constant/polyMesh", "faceZones", NULL);
    char line[160];
    snprintf(line, sizeof line, "%d\n(\n", pl->n_face_zones);
    foam_puts(o, line);
    for (int j = 0; j < pl->n_face_zones; j++) {
        snprintf(line, sizeof line, "    region%d_to_region%d\n    {\n        type faceZone;\n",
                 (int)pl->face_zone_pair[2 * j], (int)pl->face_zone_pair[2 * j + 1]);
        foam_puts(o, line);
        const int64_t b = pl->zone_face_start[j], n = pl->zone_face_start[j + 1] - b;
        foam_put_list(o, "faceLabels", "label", pl->zone_face + b, NULL, n);
        foam_put_list(o, "flipMap", "bool", NULL, pl->zone_flip + b, n);
        foam_puts(o, "    }\n");
    }
    foam_puts(o, ")\n");
}

/* The system/ files OpenFOAM's mesh tools need (checkMesh reads all
 * three): minimal, for the user to complete for a solver run. */
enum { FOAM_N_SYSTEM = 3 };
static const char *const foam_system_files[FOAM_N_SYSTEM] = {"controlDict", "fvSchemes",
                                                             "fvSolution"};

static void foam_write_system(foam_out *o, int which)
{
    foam_header(o, "dictionary", "system", foam_system_files[which], NULL);
    if (which == 0)
        foam_puts(o,
                  "// Minimal settings, enough for checkMesh and the mesh utilities;\n"
                  "// set application, endTime, deltaT etc. for a solver run.\n"
                  "startFrom       startTime;\n"
                  "startTime       0;\n"
                  "stopAt          endTime;\n"
                  "endTime         1;\n"
                  "deltaT          1;\n"
                  "writeControl    timeStep;\n"
                  "writeInterval   1;\n"
                  "purgeWrite      0;\n"
                  "writeFormat     ascii;\n"
                  "writePrecision  17;\n"
                  "writeCompression off;\n"
                  "timeFormat      general;\n"
                  "timePrecision   6;\n"
                  "runTimeModifiable false;\n");
    else if (which == 1)
        foam_puts(o,
                  "// Placeholder discretisation schemes: choose them for your solver.\n"
                  "ddtSchemes           { default Euler; }\n"
                  "gradSchemes          { default Gauss linear; }\n"
                  "divSchemes           { default none; }\n"
                  "laplacianSchemes     { default Gauss linear corrected; }\n"
                  "interpolationSchemes { default linear; }\n"
                  "snGradSchemes        { default corrected; }\n");
    else
        foam_puts(o, "// Placeholder: add the solvers and algorithm settings of your solver.\n"
                     "solvers\n{\n}\n");
}

/* ---- files and directories ------------------------------------------------ */

typedef enum { FOAM_POINTS, FOAM_FACES, FOAM_OWNER, FOAM_NEIGHBOUR, FOAM_BOUNDARY,
               FOAM_CELLZONES, FOAM_FACEZONES, FOAM_SYSTEM0 } foam_file; /* FOAM_SYSTEM0 + i: foam_system_files[i] */

/* Writes one file at path (a fresh name in a staging directory, or a
 * vc_tmpfile when tmp is set). report names the file in messages. */
static int foam_write_file(const char *path, const char *report, foam_file what,
                           const vc_polymesh *m, const foam_plan *pl, int tmp, vc_error *err)
{
    vc_tmpfile t = {0};
    FILE *fp;
    if (tmp) {
        if (vc_tmpfile_open(&t, path, err) != 0)
            return err ? err->code : VC_EIO;
        fp = (FILE *)t.fp;
    } else {
        fp = fopen(path, "wb");
        if (!fp)
            return vc_error_set(err, VC_EIO, "%s: cannot write: %s", report, strerror(errno));
    }
    foam_out o = {fp, malloc(FOAM_BUF), 0, FOAM_BUF, 0};
    if (!o.buf) {
        if (tmp)
            vc_tmpfile_discard(&t);
        else
            fclose(fp);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", report);
    }
    switch (what) {
    case FOAM_POINTS: foam_write_points(&o, m, pl); break;
    case FOAM_FACES: foam_write_faces(&o, m, pl); break;
    case FOAM_OWNER: foam_write_cells(&o, m, pl, 1); break;
    case FOAM_NEIGHBOUR: foam_write_cells(&o, m, pl, 0); break;
    case FOAM_BOUNDARY: foam_write_boundary(&o, pl); break;
    case FOAM_CELLZONES: foam_write_cell_zones(&o, pl); break;
    case FOAM_FACEZONES: foam_write_face_zones(&o, pl); break;
    default: foam_write_system(&o, (int)what - FOAM_SYSTEM0); break;
    }
    foam_flush(&o);
    free(o.buf);
    int e = o.err_no;
    if (tmp) {
        if (e) {
            vc_tmpfile_discard(&t);
        } else if (vc_tmpfile_commit(&t, err) != 0) {
            return err ? err->code : VC_EIO; /* the message names the path */
        }
    } else {
        if (fflush(fp) != 0 && !e)
            e = errno ? errno : EIO;
        if (fclose(fp) != 0 && !e)
            e = errno ? errno : EIO;
    }
    if (e == ENOMEM)
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", report);
    if (e)
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", report, strerror(e));
    return VC_OK;
}

static const char *const foam_mesh_files[7] = {"points", "faces", "owner", "neighbour",
                                               "boundary", "cellZones", "faceZones"};

/* Writes the five polyMesh files into the existing directory dir. */
static int foam_write_polymesh(const char *dir, const char *case_dir, const vc_polymesh *m,
                               const foam_plan *pl, vc_error *err)
{
    /* the zones with several regions only */
    for (int i = 0; i < (pl->patches.n_labels > 1 ? 7 : 5); i++) {
        char *path = vc_path_join(dir, foam_mesh_files[i]);
        char report[4200];
        snprintf(report, sizeof report, "%s/constant/polyMesh/%s", case_dir,
                 foam_mesh_files[i]);
        if (!path)
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", case_dir);
        int rc = foam_write_file(path, report, (foam_file)i, m, pl, 0, err);
        free(path);
        if (rc != VC_OK)
            return rc;
    }
    return VC_OK;
}

/* Writes the system/ files into the directory dir; with only_missing, the
 * ones that do not exist yet, each through a temporary file. added[i] tells
 * which were written. */
static int foam_write_system_files(const char *dir, const char *case_dir, const vc_polymesh *m,
                                   const foam_plan *pl, int only_missing, int *added,
                                   vc_error *err)
{
    for (int i = 0; i < FOAM_N_SYSTEM; i++)
        added[i] = 0;
    for (int i = 0; i < FOAM_N_SYSTEM; i++) {
        char *path = vc_path_join(dir, foam_system_files[i]);
        char report[4200];
        snprintf(report, sizeof report, "%s/system/%s", case_dir, foam_system_files[i]);
        if (!path)
            return vc_error_set(err, VC_ENOMEM, "%s: out of memory", case_dir);
        struct stat st;
        int rc = VC_OK;
        if (!only_missing || lstat(path, &st) != 0) {
            rc = foam_write_file(path, report,
                                 (foam_file)(FOAM_SYSTEM0 + i), m, pl, only_missing, err);
            added[i] = rc == VC_OK;
        }
        free(path);
        if (rc != VC_OK)
            return rc;
    }
    return VC_OK;
}

static int foam_mkdir(const char *path, const char *report, vc_error *err)
{
    if (mkdir(path, 0777) != 0)
        return vc_error_set(err, VC_EIO, "%s: cannot create: %s", report, strerror(errno));
    return VC_OK;
}

/* A new case: everything in CASE_DIR.tmp.XXXXXX (a tracked vc_tmpdir),
 * renamed at the end. */
static int foam_write_new_case(const char *case_dir, const vc_polymesh *m, const foam_plan *pl,
                               vc_error *err)
{
    vc_tmpdir sd;
    if (vc_tmpdir_create(&sd, case_dir, "tmp", err) != VC_OK)
        return err ? err->code : VC_EIO;
    const char *stage = sd.tmp_path;
    char *constant = vc_path_join(stage, "constant");
    char *poly = constant ? vc_path_join(constant, "polyMesh") : NULL;
    char *system = vc_path_join(stage, "system");
    int added[FOAM_N_SYSTEM];
    int rc = VC_OK;
    if (!constant || !poly || !system)
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", case_dir);
    if (rc == VC_OK)
        rc = foam_mkdir(constant, case_dir, err);
    if (rc == VC_OK)
        rc = foam_mkdir(poly, case_dir, err);
    if (rc == VC_OK)
        rc = foam_mkdir(system, case_dir, err);
    if (rc == VC_OK)
        rc = foam_write_polymesh(poly, case_dir, m, pl, err);
    if (rc == VC_OK)
        rc = foam_write_system_files(system, case_dir, m, pl, 0, added, err);
    if (rc == VC_OK)
        rc = vc_tmpdir_commit(&sd, err);
    if (rc != VC_OK) {
        vc_remove_tree(sd.tmp_path);
        vc_tmpdir_drop(&sd);
    }
    free(constant);
    free(poly);
    free(system);
    return rc;
}

/* An existing case directory: a new constant/polyMesh swapped in, and
 * system/controlDict added when missing. */
static int foam_write_into_case(const char *case_dir, const vc_polymesh *m, const foam_plan *pl,
                                vc_error *err)
{
    char *constant = vc_path_join(case_dir, "constant");
    char *poly = constant ? vc_path_join(constant, "polyMesh") : NULL;
    char *system = vc_path_join(case_dir, "system");
    vc_tmpdir sd = {NULL, NULL, -1};
    const char *stage = NULL;
    /* constant/ and system/ made by this run: tracked (vc_outdir_make), so
     * that a signal removes them too, and removed on failure. */
    int made_constant = 0, made_system = 0, have_old = 0;
    int constant_slot = -1, system_slot = -1;
    int added[FOAM_N_SYSTEM] = {0};
    struct stat st;
    int rc = VC_OK;
    if (!constant || !poly || !system)
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory", case_dir);

    /* constant/ and constant/polyMesh must be directories when present. */
    if (rc == VC_OK) {
        if (stat(constant, &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                rc = vc_error_set(err, VC_EIO, "%s: cannot write: Not a directory", constant);
        } else if (errno == ENOENT) {
            rc = vc_outdir_make(constant, constant, &constant_slot, err);
            made_constant = rc == VC_OK;
        } else {
            rc = vc_error_set(err, VC_EIO, "%s: cannot write: %s", constant, strerror(errno));
        }
    }
    if (rc == VC_OK) {
        if (lstat(poly, &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                rc = vc_error_set(err, VC_EIO, "%s: cannot write: Not a directory", poly);
            else
                have_old = 1;
        } else if (errno != ENOENT) {
            rc = vc_error_set(err, VC_EIO, "%s: cannot write: %s", poly, strerror(errno));
        }
    }
    if (rc == VC_OK) {
        rc = vc_tmpdir_create(&sd, poly, "tmp", err);
        stage = sd.tmp_path;
    }
    if (rc == VC_OK)
        rc = foam_write_polymesh(stage, case_dir, m, pl, err);

    /* The system/ files, only those missing. */
    if (rc == VC_OK) {
        if (stat(system, &st) != 0) {
            rc = vc_outdir_make(system, system, &system_slot, err);
            made_system = rc == VC_OK;
        } else if (!S_ISDIR(st.st_mode)) {
            rc = vc_error_set(err, VC_EIO, "%s: cannot write: Not a directory", system);
        }
    }
    if (rc == VC_OK)
        rc = foam_write_system_files(system, case_dir, m, pl, 1, added, err);

    /* The swap: old polyMesh aside, new one in, old one removed (or kept
     * by the tracker until the outputs are: a signal puts it back). */
    if (rc == VC_OK)
        rc = have_old ? vc_tmpdir_replace(&sd, err) : vc_tmpdir_commit(&sd, err);
    if (rc != VC_OK) {
        if (sd.tmp_path) {
            vc_remove_tree(sd.tmp_path);
            vc_tmpdir_drop(&sd);
        }
        for (int i = 0; i < FOAM_N_SYSTEM && system; i++)
            if (added[i]) {
                char *f = vc_path_join(system, foam_system_files[i]);
                if (f)
                    unlink(f);
                free(f);
            }
        if (made_system)
            vc_outdir_unmake(system, system_slot);
        if (made_constant)
            vc_outdir_unmake(constant, constant_slot);
    }
    free(constant);
    free(poly);
    free(system);
    return rc;
}

int vc_write_openfoam(const vc_polymesh *m, const char *case_dir, vc_error *err)
{
    return vc_write_openfoam_typed(m, case_dir, NULL, 0, err);
}

int vc_write_openfoam_typed(const vc_polymesh *m, const char *case_dir,
                            const vc_foam_patch_type *types, int n_types, vc_error *err)
{
    for (int i = 0; i < n_types; i++) {
        static const char *const ok[] = {"patch", "wall", "symmetryPlane", "symmetry", "empty"};
        int known = 0;
        for (size_t j = 0; j < sizeof ok / sizeof *ok; j++)
            known |= types[i].type && !strcmp(types[i].type, ok[j]);
        if (!types[i].name || !known)
            return vc_error_set(err, VC_EPARAM, "%s: patch type '%s' for '%s': expected patch, "
                                "wall, symmetryPlane, symmetry or empty", case_dir,
                                types[i].type ? types[i].type : "", types[i].name ? types[i].name : "");
    }
    if (!m || !case_dir || !*case_dir)
        return vc_error_set(err, VC_EPARAM, "OpenFOAM case directory is empty");
    /* "case/" names the same directory as "case"; the staging name needs the
     * latter. */
    size_t n = strlen(case_dir);
    while (n > 1 && case_dir[n - 1] == '/')
        n--;
    char *dir = malloc(n + 1);
    if (!dir)
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", case_dir);
    memcpy(dir, case_dir, n);
    dir[n] = 0;
    case_dir = dir;
    foam_plan pl;
    int rc = foam_plan_build(m, case_dir, types, n_types, &pl, err);
    if (rc != VC_OK) {
        free(dir);
        return rc;
    }
    struct stat st;
    if (stat(case_dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            rc = vc_error_set(err, VC_EIO, "%s: cannot write: Not a directory", case_dir);
        else
            rc = foam_write_into_case(case_dir, m, &pl, err);
    } else if (errno == ENOENT) {
        rc = foam_write_new_case(case_dir, m, &pl, err);
    } else {
        rc = vc_error_set(err, VC_EIO, "%s: cannot write: %s", case_dir, strerror(errno));
    }
    foam_plan_free(&pl);
    free(dir);
    return rc;
}
