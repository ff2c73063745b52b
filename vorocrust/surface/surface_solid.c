/* Whether a checked triangle surface can bound a volume
 * (vc_surface_check_solid): precision of the coordinates, zero-area
 * triangles, repeated triangles, self-intersections (self_intersection.c)
 * and enclosed volume, all on coordinates scaled by a power of two so that
 * the verdicts are scale-free. docs/input-checks.md describes the checks. */
#include "vorocrust/surface.h"
#include "surface/self_intersection.h"
#include "util/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Beyond VC_SOLID_MAX_COORDINATE_RATIO (the largest |coordinate| over the
 * diagonal), double precision keeps fewer than about 2^22 steps across the
 * model. A triangle is of zero area when |cross| <= VC_SOLID_ZERO_AREA *
 * longest^2; the enclosed volume is negligible at or below
 * VC_SOLID_MIN_VOLUME_RATIO of the bounding box's. */
#define MAX_COORDINATE_RATIO VC_SOLID_MAX_COORDINATE_RATIO
#define ZERO_AREA VC_SOLID_ZERO_AREA
#define MIN_VOLUME_RATIO VC_SOLID_MIN_VOLUME_RATIO

/* ---- Repeated triangles: a hash table on the sorted vertex triple ---- */

typedef struct slot {
    int64_t a, b, c;  /* sorted vertices; a == -1 for an empty slot */
    int64_t first[2]; /* first triangle of each orientation, -1 */
} slot;

static uint64_t hash3(int64_t a, int64_t b, int64_t c)
{
    uint64_t h = (uint64_t)a * 0x9e3779b97f4a7c15ULL;
    h ^= (uint64_t)b + 0x632be59bd9b4e019ULL + (h << 6) + (h >> 2);
    h ^= (uint64_t)c + 0x85ebca6b2c1b3c2dULL + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 29;
    return h;
}

static void set_first(int64_t *pair, int64_t a, int64_t b)
{
    if (pair[0] < 0) {
        pair[0] = a;
        pair[1] = b;
    }
}

/* Counts the triangles whose three vertices repeat an earlier triangle's,
 * with the same orientation and with the opposite one; the first pair of
 * each kind is the one whose later triangle comes first. */
static int repeated_triangles(const vc_surface *s, vc_solid_report *o)
{
    int64_t nt = s->n_triangles;
    uint64_t cap = 16;
    while (cap < 2 * (uint64_t)nt)
        cap <<= 1;
    slot *tab = malloc(cap * sizeof *tab);
    if (!tab)
        return -1;
    for (uint64_t i = 0; i < cap; i++)
        tab[i].a = -1;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *v = s->tri + 3 * t;
        int k = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
        int64_t a = v[k], p = v[(k + 1) % 3], q = v[(k + 2) % 3];
        int par = p < q ? 0 : 1; /* 0: (a, p, q) is increasing */
        int64_t b = p < q ? p : q, c = p < q ? q : p;
        uint64_t h = hash3(a, b, c) & (cap - 1);
        while (tab[h].a >= 0 && !(tab[h].a == a && tab[h].b == b && tab[h].c == c))
            h = (h + 1) & (cap - 1);
        slot *e = &tab[h];
        if (e->a < 0) {
            e->a = a;
            e->b = b;
            e->c = c;
            e->first[0] = e->first[1] = -1;
        }
        if (e->first[par] >= 0) {
            o->n_repeated_same++;
            set_first(o->first_repeated_same, e->first[par], t);
        } else if (e->first[1 - par] >= 0) {
            o->n_repeated_opposite++;
            set_first(o->first_repeated_opposite, e->first[1 - par], t);
        }
        if (e->first[par] < 0)
            e->first[par] = t;
    }
    free(tab);
    return 0;
}

/* ---- The checks ---- */

/* The vertex numbers (1-based) of triangle t, for messages. */
#define TRI_VERTS(s, t) (long long)(s)->tri[3 * (t)] + 1, (long long)(s)->tri[3 * (t) + 1] + 1, \
                        (long long)(s)->tri[3 * (t) + 2] + 1

int vc_surface_check_solid(const vc_surface *s, const vc_surface_report *rep, vc_solid_report *out,
                           vc_error *err)
{
    vc_solid_report o_local, *o = out ? out : &o_local;
    memset(o, 0, sizeof *o);
    o->first_zero_area = -1;
    o->first_repeated_same[0] = o->first_repeated_same[1] = -1;
    o->first_repeated_opposite[0] = o->first_repeated_opposite[1] = -1;
    o->first_self_intersection[0] = o->first_self_intersection[1] = -1;
    o->volume_ratio = NAN;
    const char *name = rep && rep->name[0] ? rep->name : "surface";
    int64_t nv = s->n_vertices, nt = s->n_triangles;
    if (nt <= 0 || nv <= 0)
        return vc_error_set(err, VC_EINPUT, "%s: no triangles", name);
    for (int64_t i = 0; i < 3 * nv; i++)
        if (!isfinite(s->xyz[i]))
            return vc_error_set(err, VC_EINPUT, "%s: vertex %lld has a non-finite coordinate (%g)", name,
                                (long long)(i / 3 + 1), s->xyz[i]);
    for (int64_t k = 0; k < 3 * nt; k++)
        if (s->tri[k] < 0 || s->tri[k] >= nv)
            return vc_error_set(err, VC_EINPUT, "%s: triangle %lld refers to vertex %lld of %lld", name,
                                (long long)(k / 3 + 1), (long long)s->tri[k] + 1, (long long)nv);

    /* Scale: first by the largest |coordinate| (so nothing below can
     * overflow), then by the diagonal. Powers of two: exact. */
    double bb[6], M = 0;
    for (int k = 0; k < 3; k++)
        bb[k] = bb[k + 3] = s->xyz[k];
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            double x = s->xyz[3 * i + k], ax = fabs(x);
            bb[k] = x < bb[k] ? x : bb[k];
            bb[k + 3] = x > bb[k + 3] ? x : bb[k + 3];
            M = ax > M ? ax : M;
        }
    if (M == 0)
        return vc_error_set(err, VC_EINPUT, "%s: every vertex is at the origin", name);
    int eM;
    frexp(M, &eM);
    double ext[3], emax = 0;
    for (int k = 0; k < 3; k++) {
        ext[k] = ldexp(bb[k + 3], -eM) - ldexp(bb[k], -eM);
        emax = fmax(emax, ext[k]);
    }
    if (emax == 0)
        return vc_error_set(err, VC_EINPUT, "%s: all %lld vertices coincide", name, (long long)nv);
    double diag = 0;
    for (int k = 0; k < 3; k++)
        diag += (ext[k] / emax) * (ext[k] / emax);
    diag = emax * sqrt(diag); /* in units of 2^eM */
    o->coordinate_ratio = ldexp(M, -eM) / diag;
    int eD;
    frexp(diag, &eD);
    int shift = -(eM + eD); /* scaled diagonal in [0.5, 1) */
    double *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    unsigned char *zero = calloc((size_t)nt, 1);
    double *tri_vol6 = malloc(sizeof(double) * (size_t)nt); /* NULL: the whole sum only */
    if (!xyz || !zero) {
        free(xyz);
        free(zero);
        free(tri_vol6);
        return vc_error_set(err, VC_ENOMEM, "%s: out of memory checking the surface", name);
    }
    /* Two factors, each representable; the product is exact (the middle
     * value lies between the two). */
    const double f1 = ldexp(1.0, shift / 2), f2 = ldexp(1.0, shift - shift / 2);
    for (int64_t i = 0; i < 3 * nv; i++)
        xyz[i] = s->xyz[i] * f1 * f2;
    double c[3], box[3];
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * ldexp(bb[k], shift) + 0.5 * ldexp(bb[k + 3], shift);
        box[k] = ldexp(bb[k + 3], shift) - ldexp(bb[k], shift);
    }

    /* Zero-area triangles and the enclosed volume (about the box centre). */
    double vol6 = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *p[3];
        double r[3][3], u[3], v[3], w[3];
        for (int j = 0; j < 3; j++) {
            p[j] = xyz + 3 * s->tri[3 * t + j];
            for (int k = 0; k < 3; k++)
                r[j][k] = p[j][k] - c[k];
        }
        for (int k = 0; k < 3; k++) {
            u[k] = p[1][k] - p[0][k];
            v[k] = p[2][k] - p[0][k];
            w[k] = p[2][k] - p[1][k];
        }
        double lu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        double lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        double lmax = lu > lv ? lu : lv;
        lmax = lw > lmax ? lw : lmax;
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        if (sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) <= ZERO_AREA * lmax) {
            zero[t] = 1;
            if (o->n_zero_area++ == 0)
                o->first_zero_area = t;
        }
        const double d6 = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                          r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                          r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        vol6 += d6;
        if (tri_vol6)
            tri_vol6[t] = d6;
    }
    int check_volume = !rep || (rep->n_boundary_edges == 0 && rep->n_inconsistent_edges == 0);
    double box_volume = box[0] * box[1] * box[2];
    /* Each component's volume counts whatever its orientation: an assembly
     * with one part inside out sums to the difference (two equal cubes, one
     * reversed, to 0), yet encloses volume; vc_mesh reverses such a part. */
    double enclosed6 = fabs(vol6);
    if (check_volume) {
        int64_t *parent = malloc(sizeof(int64_t) * (size_t)nv);
        double *part6 = calloc((size_t)nv, sizeof(double));
        if (parent && part6 && tri_vol6) {
            vc_uf_init(parent, nv);
            for (int64_t t = 0; t < nt; t++) {
                vc_uf_unite(parent, s->tri[3 * t], s->tri[3 * t + 1]);
                vc_uf_unite(parent, s->tri[3 * t], s->tri[3 * t + 2]);
            }
            for (int64_t t = 0; t < nt; t++)
                part6[vc_uf_find(parent, s->tri[3 * t])] += tri_vol6[t];
            enclosed6 = 0;
            for (int64_t v = 0; v < nv; v++)
                enclosed6 += fabs(part6[v]);
        }
        free(parent);
        free(part6);
        o->volume_ratio = box_volume > 0 ? enclosed6 / 6.0 / box_volume : 0;
    }

    int rc = 0;
    if (repeated_triangles(s, o) ||
        vc_self_intersections(xyz, s->tri, nt, zero, &o->n_self_intersections, o->first_self_intersection))
        rc = vc_error_set(err, VC_ENOMEM, "%s: out of memory checking the surface", name);
    free(xyz);
    free(zero);
    free(tri_vol6);
    if (rc)
        return rc;

    /* The first problem, in the documented order. */
    if (o->coordinate_ratio > MAX_COORDINATE_RATIO)
        return vc_error_set(err, VC_EINPUT,
                            "%s: the coordinates (up to %.3g) are %.2g times the model's size (diagonal %.3g): "
                            "double precision rounds its shape away (vertices closer than %.2g coincide, "
                            "triangles lose their area); translate the model near the origin",
                            name, M, o->coordinate_ratio, ldexp(diag, eM), ldexp(M, -52));
    if (o->n_zero_area) {
        int64_t t = o->first_zero_area;
        return vc_error_set(err, VC_EINPUT,
                            "%s: %lld zero-area triangles (first: triangle %lld, vertices %lld %lld %lld): "
                            "a surface with collinear or coincident corners cannot bound a volume; remove "
                            "them (collapse their shortest edge) and export again",
                            name, (long long)o->n_zero_area, (long long)t + 1, TRI_VERTS(s, t));
    }
    if (o->n_repeated_same) {
        const int64_t *f = o->first_repeated_same;
        return vc_error_set(err, VC_EINPUT,
                            "%s: %lld triangles repeat an earlier one with the same orientation (first: "
                            "triangles %lld and %lld, vertices %lld %lld %lld): remove the copies",
                            name, (long long)o->n_repeated_same, (long long)f[0] + 1, (long long)f[1] + 1,
                            TRI_VERTS(s, f[0]));
    }
    if (o->n_self_intersections) {
        const int64_t *f = o->first_self_intersection;
        return vc_error_set(err, VC_EINPUT,
                            "%s: the surface intersects itself: %lld pairs of triangles cross or touch "
                            "(first: triangles %lld and %lld); repair it (merge the overlapping parts "
                            "with a boolean union, or remesh), or mesh the union of its parts (vorocrust mesh "
                            "without --no-union)",
                            name, (long long)o->n_self_intersections, (long long)f[0] + 1, (long long)f[1] + 1);
    }
    if (check_volume && !(o->volume_ratio > MIN_VOLUME_RATIO)) {
        static const char axis[3] = {'x', 'y', 'z'};
        for (int k = 0; k < 3; k++)
            if (box[k] == 0)
                return vc_error_set(err, VC_EINPUT,
                                    "%s: every vertex lies in the plane %c = %.9g: a flat surface encloses "
                                    "no volume; give the model a thickness",
                                    name, axis[k], bb[k]);
        return vc_error_set(err, VC_EINPUT,
                            "%s: the enclosed volume is %.2g of the bounding box's (at most %g): a flat or "
                            "zero-thickness surface encloses no volume; give the model a thickness",
                            name, o->volume_ratio, MIN_VOLUME_RATIO);
    }
    o->solid = 1;
    return 0;
}
