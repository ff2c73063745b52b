/* TOUGH2 / TOUGH3 MESH file: ELEME and CONNE records in the fixed 80-column
 * format of the TOUGH2 user's guide (see include/vorocrust/io.h).
 *
 * Fixed columns hold ten characters per number. Fortran reads an E10.4
 * field as any real number written in its ten columns, so each number is
 * written in the ten-character form that keeps the most significant
 * digits (fixed or exponent notation): coordinates with large offsets
 * keep nine digits where "0.1234E+07" would keep four. */
#include "vorocrust/io.h"
#include "io/io_patches.h"

#include "io/tmpfile.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* names: a letter, two base-36 characters, two digits (TOUGH2 reads the
 * last two columns of a name as an integer) */
#define NAME_CAPACITY (26LL * 36 * 36 * 100)
/* the volume of a boundary element: it never changes state */
#define BOUNDARY_VOLUME 1e50

static void element_name(int64_t i, char out[6])
{
    static const char b36[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    const int64_t per_letter = 36 * 36 * 100;
    const int64_t r = i % per_letter;
    out[0] = (char)('A' + i / per_letter);
    out[1] = b36[r / (36 * 100)];
    out[2] = b36[(r / 100) % 36];
    out[3] = (char)('0' + (r % 100) / 10);
    out[4] = (char)('0' + r % 10);
    out[5] = 0;
}

/* x in ten characters, right-aligned, as many significant digits as fit.
 * Returns -1 when it cannot be written in ten (|x| beyond 1e99 or below
 * 1e-99 but not zero: no such mesh value is meaningful). */
static int fmt10(double x, char out[11])
{
    char best[32] = "", buf[32];
    int best_digits = -1;
    if (x == 0) {
        snprintf(out, 11, "%10s", "0.");
        return 0;
    }
    if (!isfinite(x) || fabs(x) >= 1e99 || fabs(x) < 1e-99)
        return -1;
    /* exponent notation: d.ddde+XX */
    for (int p = 9; p >= 0; p--) {
        int n = snprintf(buf, sizeof buf, "%.*e", p, x);
        if (n <= 10) {
            best_digits = p + 1;
            memcpy(best, buf, (size_t)n + 1);
            break;
        }
    }
    /* fixed notation, when it keeps more digits (and does not round to 0) */
    const int lead = fabs(x) >= 1 ? (int)floor(log10(fabs(x))) + 1 : 0;
    for (int p = 9; p >= 0; p--) {
        int n = snprintf(buf, sizeof buf, "%.*f", p, x);
        if (n > 10)
            continue;
        int digits = lead > 0 ? lead + p : p + (int)floor(log10(fabs(x))) + 1;
        if (digits > best_digits && strtod(buf, NULL) != 0) {
            best_digits = digits;
            memcpy(best, buf, (size_t)n + 1);
        }
        break;
    }
    if (best_digits < 0)
        return -1;
    /* a fixed number without a decimal point would read as an integer:
     * Fortran's E edit accepts it, but keep the point for clarity */
    if (!strchr(best, '.') && !strchr(best, 'e') && strlen(best) < 10)
        strcat(best, ".");
    snprintf(out, 11, "%10.10s", best);
    return 0;
}

typedef struct tough_out {
    FILE *fp;
    int bad;     /* a write failed */
    int range;   /* a number does not fit ten columns */
} tough_out;

static void put_number(tough_out *o, double x)
{
    char s[11];
    if (fmt10(x, s)) {
        o->range = 1;
        memcpy(s, "         0", 11);
    }
    if (fputs(s, o->fp) < 0)
        o->bad = 1;
}

static void element(tough_out *o, const char *name, int32_t label, double volume, const double x[3])
{
    char mat[8];
    snprintf(mat, sizeof mat, "R%04d", (int)(label % 10000));
    /* name, NSEQ and NADD blank, material, volume, AHTX and PMX blank, X Y Z */
    if (fprintf(o->fp, "%s%10s%s", name, "", mat) < 0)
        o->bad = 1;
    put_number(o, volume);
    if (fprintf(o->fp, "%20s", "") < 0)
        o->bad = 1;
    for (int k = 0; k < 3; k++)
        put_number(o, x[k]);
    if (fputc('\n', o->fp) == EOF)
        o->bad = 1;
}

/* ISOT: the axis the connection runs closest to (1 x, 2 y, 3 z), so that
 * the ROCKS block's directional permeabilities apply approximately. */
static int isot_of(const double d[3])
{
    const double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]);
    return ax >= ay && ax >= az ? 1 : ay >= az ? 2 : 3;
}

static void connection(tough_out *o, const char *n1, const char *n2, const double x1[3],
                       const double x2[3], double d1, double d2, double area)
{
    const double d[3] = {x2[0] - x1[0], x2[1] - x1[1], x2[2] - x1[2]};
    const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    /* BETAX: cosine of the angle between gravity (-z) and the line from
     * element 1 to element 2: positive when element 1 lies above */
    const double beta = len > 0 ? -d[2] / len : 0;
    if (fprintf(o->fp, "%s%s%15s%5d", n1, n2, "", isot_of(d)) < 0)
        o->bad = 1;
    put_number(o, d1);
    put_number(o, d2);
    put_number(o, area);
    put_number(o, beta);
    if (fputc('\n', o->fp) == EOF)
        o->bad = 1;
}

int vc_write_tough(const vc_polymesh *m, const char *path, vc_error *err)
{
    if (!m || !path || !*path)
        return vc_error_set(err, VC_EPARAM, "vc_write_tough: no mesh or no path");
    if (m->n_cells > 0 && (!m->seed_xyz || !m->cell_seed || !m->cell_volume || !m->face_area))
        return vc_error_set(err, VC_EINPUT, "%s: the mesh lacks seeds, volumes or face areas",
                            path);
    const int64_t ni = m->n_interior_faces, nb = m->n_faces - m->n_interior_faces;
    if (m->n_cells + nb > NAME_CAPACITY)
        return vc_error_set(err, VC_EINPUT,
                            "%s: %" PRId64 " cells and %" PRId64 " boundary elements exceed the "
                            "%lld five-character element names TOUGH reads",
                            path, m->n_cells, nb, (long long)NAME_CAPACITY);
    vc_boundary_patches bp;
    const int prc = vc_io_boundary_patches(m, path, &bp, err);
    if (prc)
        return prc;
    /* boundary elements patch by patch, faces in mesh order within each:
     * element n_cells + belem[f - ni] */
    int64_t *belem = malloc(sizeof(int64_t) * (size_t)(nb + 1));
    int64_t *start = malloc(sizeof(int64_t) * (size_t)(bp.n_patches + 1));
    if (!belem || !start) {
        free(belem);
        free(start);
        vc_boundary_patches_free(&bp);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    int64_t s = 0;
    for (int k = 0; k < bp.n_patches; k++) {
        start[k] = s;
        s += bp.size[k];
    }
    for (int64_t i = 0; i < nb; i++)
        belem[i] = start[bp.face_patch[i]]++;

    vc_tmpfile t;
    if (vc_tmpfile_open(&t, path, err) != 0) {
        free(belem);
        free(start);
        vc_boundary_patches_free(&bp);
        return err ? err->code : VC_EIO;
    }
    tough_out o = {(FILE *)t.fp, 0, 0};
    char n1[6], n2[6];
    if (fputs("ELEME----1----*----2----*----3----*----4----*----5----*----6----*----7----*----8\n",
              o.fp) < 0)
        o.bad = 1;
    for (int64_t c = 0; c < m->n_cells && !o.bad; c++) {
        element_name(c, n1);
        element(&o, n1, m->cell_region ? m->cell_region[c] : 1, m->cell_volume[c],
                m->seed_xyz + 3 * m->cell_seed[c]);
    }
    /* the boundary elements in their order: invert belem */
    int64_t *face_of = malloc(sizeof(int64_t) * (size_t)(nb + 1));
    if (!face_of) {
        vc_tmpfile_discard(&t);
        free(belem);
        free(start);
        vc_boundary_patches_free(&bp);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory", path);
    }
    for (int64_t i = 0; i < nb; i++)
        face_of[belem[i]] = ni + i;
    for (int64_t e = 0; e < nb && !o.bad; e++) {
        const int64_t f = face_of[e];
        double x[3];
        vc_polymesh_face_seed_point(m, f, x);
        element_name(m->n_cells + e, n1);
        const int64_t c = m->face_owner[f];
        element(&o, n1, m->cell_region ? m->cell_region[c] : 1, BOUNDARY_VOLUME, x);
    }
    if (fputs("\nCONNE----1----*----2----*----3----*----4----*----5----*----6----*----7----*----8\n",
              o.fp) < 0)
        o.bad = 1;
    for (int64_t f = 0; f < ni && !o.bad; f++) {
        const int64_t a = m->face_owner[f], b = m->face_neighbour[f];
        const double *xa = m->seed_xyz + 3 * m->cell_seed[a], *xb = m->seed_xyz + 3 * m->cell_seed[b];
        const double half = 0.5 * sqrt((xb[0] - xa[0]) * (xb[0] - xa[0]) +
                                       (xb[1] - xa[1]) * (xb[1] - xa[1]) +
                                       (xb[2] - xa[2]) * (xb[2] - xa[2]));
        element_name(a, n1);
        element_name(b, n2);
        connection(&o, n1, n2, xa, xb, half, half, m->face_area[f]);
    }
    for (int64_t e = 0; e < nb && !o.bad; e++) {
        const int64_t f = face_of[e], a = m->face_owner[f];
        const double *xa = m->seed_xyz + 3 * m->cell_seed[a];
        double x[3];
        vc_polymesh_face_seed_point(m, f, x);
        const double d1 = sqrt((x[0] - xa[0]) * (x[0] - xa[0]) + (x[1] - xa[1]) * (x[1] - xa[1]) +
                               (x[2] - xa[2]) * (x[2] - xa[2]));
        element_name(a, n1);
        element_name(m->n_cells + e, n2);
        /* the boundary element sits on the face: a nodal distance of zero */
        connection(&o, n1, n2, xa, x, d1, 0.0, m->face_area[f]);
    }
    if (fputs("\n", o.fp) < 0)
        o.bad = 1;
    free(face_of);
    free(belem);
    free(start);
    vc_boundary_patches_free(&bp);
    if (o.bad || ferror(o.fp)) {
        const int e = errno;
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EIO, "%s: cannot write: %s", path, strerror(e ? e : EIO));
    }
    if (o.range) {
        vc_tmpfile_discard(&t);
        return vc_error_set(err, VC_EINPUT,
                            "%s: a coordinate, volume or area does not fit TOUGH's ten columns "
                            "(beyond 1e99 or below 1e-99): scale the model", path);
    }
    return vc_tmpfile_commit(&t, err) == 0 ? VC_OK : (err ? err->code : VC_EIO);
}
