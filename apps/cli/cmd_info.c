/* vorocrust info: read a triangle surface and describe it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_util.h"
#include "commands.h"
#include "vorocrust/features.h"
#include "vorocrust/regions.h"
#include "vorocrust/surface.h"
#include "vorocrust/vorocrust.h"

/* The regions of the arrangement: what the surface bounds, and whether
 * its orientation makes it one solid (what vorocrust mesh needs). */
static int print_regions(const vc_surface *s)
{
    vc_regions r;
    vc_error err = {0, ""};
    if (vc_surface_regions(s, &r, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        return -1;
    }
    int64_t n_kind[4] = {0, 0, 0, 0};
    for (int64_t i = 0; i < r.n_regions; i++)
        n_kind[r.region[i].kind]++;
    printf("regions: %lld (%lld solid, %lld void, %lld mixed); %lld triangles between two regions",
           (long long)r.n_regions, (long long)n_kind[VC_REGION_SOLID], (long long)n_kind[VC_REGION_VOID],
           (long long)n_kind[VC_REGION_MIXED], (long long)r.n_interface);
    if (r.n_twice)
        printf(", %lld given twice", (long long)r.n_twice);
    if (r.n_walls)
        printf("; %lld walls of zero thickness (the same region on both sides, first: triangle "
               "%lld)", (long long)r.n_walls, (long long)r.first_wall + 1);
    printf("\n");
    static const char *kind[4] = {"", "solid", "void", "mixed"};
    for (int64_t i = 0; i < r.n_regions; i++) {
        const vc_region *g = &r.region[i];
        printf("region %lld: volume %.9g, %s, ", (long long)i + 1, g->volume, kind[g->kind]);
        if (g->parent >= 0)
            printf("inside region %lld", (long long)g->parent + 1);
        else
            printf("outermost");
        printf(", %lld holes, %lld triangle sides from triangle %lld\n", (long long)g->n_holes,
               (long long)g->n_sides, (long long)g->first_triangle + 1);
    }
    const int one = vc_regions_single_solid(&r);
    printf("one solid by orientation: %s\n", one > 0 ? "yes" : one < 0 ? "yes (oriented inward)" : "no");
    const int64_t n_inside_out = vc_regions_inside_out_flips(&r, NULL);
    if (n_inside_out > 0)
        printf("inside out: %lld of %lld components (normals pointing in, nothing around them); "
               "vorocrust mesh reverses them\n", (long long)n_inside_out, (long long)r.n_components);
    vc_regions_free(&r);
    return 0;
}

/* The number after option argv[i], in (lo, hi) or [lo, hi) when
 * lo_closed; 1 (after one line on stderr) when missing or out of range. */
static int number_arg(int argc, char **argv, int i, double lo, double hi, int lo_closed, const char *what,
                      double *value)
{
    char *end = NULL;
    if (i + 1 < argc)
        *value = strtod(argv[i + 1], &end);
    if (i + 1 >= argc || end == argv[i + 1] || *end || !(lo_closed ? *value >= lo : *value > lo) ||
        !(*value < hi)) {
        fprintf(stderr, "vorocrust: %s needs %s%s%s%s\n", argv[i], what, i + 1 < argc ? ", got '" : "",
                i + 1 < argc ? argv[i + 1] : "", i + 1 < argc ? "'" : "");
        return 1;
    }
    return 0;
}

static double default_max_error(void)
{
    vc_mesh_options o;
    vc_mesh_options_default(&o);
    return o.max_error;
}

static void usage(FILE *f)
{
    fprintf(f,
        "usage: vorocrust info INPUT [--require-closed] [--features [--sharp-angle DEG]\n"
        "                            [--max-error E]]\n"
        "  INPUT              triangle surface: .obj, .off, .stl (ASCII or binary), .ply\n"
        "  --require-closed   fail (exit 1) when the surface has open boundary edges\n"
        "                     or cannot bound a volume (see 'solid' below)\n"
        "  --features         also detect sharp features (thesis 6.2.2) and print the\n"
        "                     numbers of sharp edges, sharp corners, creases (open and\n"
        "                     closed) and surface patches\n"
        "  --sharp-angle DEG  theta_sharp in degrees, 0 < DEG < 180 (default %g):\n"
        "                     an edge is sharp when its triangles' normals differ by\n"
        "                     more than DEG, or it has one or more than two triangles;\n"
        "                     implies --features\n"
        "  --max-error E      the error bound of 'vorocrust mesh' (a fraction of the\n"
        "                     bounding-box diagonal, default %g; 0: none): folds over\n"
        "                     DEG on ground flat at it are noise, not sharp, and folds\n"
        "                     below DEG whose triangles leave each other's plane by\n"
        "                     more than %g bounds are sharp, as the mesh command judges\n"
        "                     them; implies --features\n"
        "Prints counts, bounding box, topology (boundary, non-manifold and\n"
        "inconsistently oriented edges, components, Euler characteristic, genus)\n"
        "and enclosed volume, then whether the surface can bound a volume ('solid':\n"
        "no repeated or zero-area triangles, no self-intersection, a volume above\n"
        "1e-9 of the bounding box's, coordinates within 1e9 times the model's size).\n"
        "Problems are printed to stderr, one line each;\n"
        "only unreadable or unusable input makes the exit code non-zero.\n",
        VC_FEATURES_DEFAULT_SHARP_ANGLE, default_max_error(), VC_VISIBLE_FOLD);
}

int vc_cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int require_closed = 0, features = 0;
    double sharp_angle = VC_FEATURES_DEFAULT_SHARP_ANGLE, max_error = default_max_error();
    vc_cli_seen seen = {{NULL}, 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        /* as every command: a second --sharp-angle must not silently win */
        if (vc_cli_repeated(&seen, "vorocrust", "vorocrust info", a))
            return 2;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--require-closed")) {
            require_closed = 1;
        } else if (!strcmp(a, "--features")) {
            features = 1;
        } else if (!strcmp(a, "--sharp-angle")) {
            if (number_arg(argc, argv, i, 0, 180, 0, "a number of degrees in (0, 180)", &sharp_angle))
                return 2;
            features = 1;
            i++;
        } else if (!strcmp(a, "--max-error")) {
            if (number_arg(argc, argv, i, 0, 1, 1, "a number in [0, 1)", &max_error))
                return 2;
            features = 1;
            i++;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "vorocrust: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        } else if (!path) {
            path = a;
        } else {
            fprintf(stderr, "vorocrust: more than one INPUT ('%s', '%s')\n", path, a);
            return 2;
        }
    }
    if (!path) {
        usage(stderr);
        return 2;
    }

    vc_surface s;
    vc_surface_report rep;
    vc_error err = {0, ""};
    if (vc_surface_read(path, &s, &rep, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        return 1;
    }
    /* Open only by rounding: welded as vorocrust mesh welds it, and the
     * lines after describe that surface */
    int64_t n_welded = 0, n_split = 0, n_open_before = rep.n_boundary_edges;
    double seam_tol = 0;
    if (rep.n_boundary_edges > 0) {
        vc_surface welded;
        vc_surface_report r;
        seam_tol = vc_surface_seam_tolerance(&s) / vc_surface_diagonal(&s);
        if (vc_surface_close_by_rounding(&s, &rep, &welded, &r, &n_welded, &n_split, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", path, err.msg);
            vc_surface_free(&s);
            return 1;
        }
        if (welded.xyz) {
            vc_surface_free(&s);
            s = welded;
            rep = r;
        }
    }
    for (int i = 0; i < rep.n_warnings; i++)
        fprintf(stderr, "vorocrust: warning: %s\n", rep.warnings[i]);
    /* Triangles that disagree on the orientation: reversed as vorocrust
     * mesh reverses them, and the lines after describe that surface */
    const int64_t n_inconsistent = rep.n_inconsistent_edges;
    int64_t n_flipped = -1;
    vc_error flip_why = {0, ""};
    if (n_inconsistent > 0) {
        unsigned char *flip = malloc((size_t)s.n_triangles + 1);
        if (flip && vc_surface_consistent_flips(&s, flip, &n_flipped, &flip_why) == 0) {
            vc_surface_reverse_triangles(&s, flip);
            rep.n_warnings = 0; /* printed above */
            if (vc_surface_check(&s, &rep, &err)) {
                fprintf(stderr, "vorocrust: %s\n", err.msg);
                free(flip);
                vc_surface_free(&s);
                return 1;
            }
        } else
            n_flipped = -1;
        free(flip);
    }
    /* Zero-area caps: the triangles across split at their vertex, as
     * vorocrust mesh splits them, and the lines after describe that surface */
    int64_t n_caps = 0, n_zero_before = rep.n_degenerate;
    if (rep.n_degenerate > 0) {
        int64_t n_left = 0;
        if (vc_surface_flip_zero_area(&s, &n_caps, &n_left, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", path, err.msg);
            vc_surface_free(&s);
            return 1;
        }
        if (n_caps > 0) {
            rep.n_warnings = 0; /* printed above */
            if (vc_surface_check(&s, &rep, &err)) {
                fprintf(stderr, "vorocrust: %s\n", err.msg);
                vc_surface_free(&s);
                return 1;
            }
        }
    }
    /* Zero-area needles: their two coincident vertices welded, as vorocrust
     * mesh welds them */
    int64_t n_needles = 0, n_zero_needles = rep.n_degenerate;
    if (rep.n_degenerate > 0) {
        vc_surface needled;
        vc_surface_report r;
        if (vc_surface_drop_needles(&s, &rep, &needled, &r, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", path, err.msg);
            vc_surface_free(&s);
            return 1;
        }
        if (needled.xyz) {
            n_needles = rep.n_degenerate - r.n_degenerate;
            vc_surface_free(&s);
            s = needled;
            rep = r;
        }
    }
    /* Turned-over needles within half the error bound: flipped as vorocrust
     * mesh flips them (before its solid check), and the lines after
     * describe that surface */
    vc_needle_flip_report needles = {0, 0, 0};
    const int needles_checked = max_error > 0 && rep.n_inconsistent_edges == 0;
    if (needles_checked) {
        if (vc_surface_flip_turned_needles(&s, 0.5 * max_error * vc_surface_diagonal(&s), &needles, &err)) {
            fprintf(stderr, "vorocrust: %s\n", err.msg);
            vc_surface_free(&s);
            return 1;
        }
        if (needles.n_flipped > 0) {
            rep.n_warnings = 0; /* printed above */
            if (vc_surface_check(&s, &rep, &err)) {
                fprintf(stderr, "vorocrust: %s\n", err.msg);
                vc_surface_free(&s);
                return 1;
            }
        }
    }
    /* Can it bound a volume? A warning, or with --require-closed on a
     * closed surface the error line at the end. */
    vc_solid_report solid;
    vc_error solid_err = {0, ""};
    int solid_rc = vc_surface_check_solid(&s, &rep, &solid, &solid_err);
    if (solid_rc == VC_ENOMEM) {
        fprintf(stderr, "vorocrust: %s\n", solid_err.msg);
        vc_surface_free(&s);
        return 1;
    }
    int closed = rep.n_boundary_edges == 0;
    if (solid_rc && !(require_closed && closed))
        fprintf(stderr, "vorocrust: warning: %s\n", solid_err.msg);

    const double *b = rep.bbox;
    printf("file: %s\n", rep.name);
    printf("reader: %s\n", rep.reader);
    printf("vertices: %lld\n", (long long)rep.n_vertices);
    printf("triangles: %lld\n", (long long)rep.n_triangles);
    printf("edges: %lld\n", (long long)rep.n_edges);
    if (rep.n_polygons_triangulated)
        printf("polygons triangulated: %lld\n", (long long)rep.n_polygons_triangulated);
    if (rep.n_duplicate_vertices)
        printf("duplicate vertices merged: %lld\n", (long long)rep.n_duplicate_vertices);
    printf("bounding box: [%.9g, %.9g] x [%.9g, %.9g] x [%.9g, %.9g]\n", b[0], b[3], b[1], b[4], b[2], b[5]);
    printf("size: %.9g x %.9g x %.9g\n", b[3] - b[0], b[4] - b[1], b[5] - b[2]);
    if (n_welded + n_split > 0)
        printf("seam welding: %lld open edges closed by welding %lld vertices within %.2g of the "
               "diagonal of another and splitting %lld triangles at vertices on their edges, as "
               "vorocrust mesh does; the lines below describe that surface\n",
               (long long)n_open_before, (long long)n_welded, seam_tol, (long long)n_split);
    if (n_needles > 0)
        printf("zero-area needles: %lld of %lld zero-area triangles removed by welding their two "
               "coincident vertices, as vorocrust mesh does; the lines below describe that "
               "surface\n", (long long)n_needles, (long long)n_zero_needles);
    if (n_caps > 0)
        printf("zero-area repair: %lld of %lld zero-area triangles were caps (a vertex on the opposite "
               "edge), the triangles across split there, as vorocrust mesh does; the lines below "
               "describe that surface\n", (long long)n_caps, (long long)n_zero_before);
    printf("boundary edges: %lld\n", (long long)rep.n_boundary_edges);
    printf("non-manifold edges: %lld\n", (long long)rep.n_nonmanifold_edges);
    printf("inconsistently oriented edges: %lld\n", (long long)n_inconsistent);
    if (n_inconsistent > 0 && n_flipped >= 0)
        printf("orientation repair: %lld triangles reversed, as vorocrust mesh reverses them (each component "
               "keeps the orientation most of its triangles have); the lines below describe that surface\n",
               (long long)n_flipped);
    else if (n_inconsistent > 0)
        printf("orientation repair: none possible (%s)\n", flip_why.msg[0] ? flip_why.msg : "out of memory");
    if (needles_checked && needles.n_flipped > 0)
        printf("turned-over needles: %lld flipped, as vorocrust mesh flips them (an apex across its long "
               "edge within half the error bound; the surface moved by at most %.3g); the lines below "
               "describe that surface\n",
               (long long)needles.n_flipped, needles.max_move);
    else if (needles_checked)
        printf("turned-over needles: 0\n");
    printf("degenerate triangles: %lld\n", (long long)rep.n_degenerate);
    int64_t n_repeated = solid.n_repeated_same + solid.n_repeated_opposite;
    printf("repeated triangles: %lld", (long long)n_repeated);
    if (n_repeated)
        printf(" (%lld with the same orientation, %lld reversed)", (long long)solid.n_repeated_same,
               (long long)solid.n_repeated_opposite);
    printf("\n");
    printf("self-intersections: %lld\n", (long long)solid.n_self_intersections);
    /* what `mesh` meshes instead (unless --no-union) */
    if (solid.n_self_intersections > 0 && closed && rep.n_inconsistent_edges == 0 && solid.n_zero_area == 0 &&
        solid.n_repeated_same == 0) {
        vc_surface u;
        vc_self_union_report ur;
        vc_error uerr = {0, ""};
        int urc = vc_surface_self_union(&s, rep.name, &u, &ur, &uerr);
        if (urc == 0) {
            printf("union: %lld triangles, volume %.9g (%lld of %lld patches inside another part dropped): "
                   "what vorocrust mesh samples\n",
                   (long long)u.n_triangles, ur.volume, (long long)ur.n_patches_dropped, (long long)ur.n_patches);
        } else {
            const size_t skip = strlen(rep.name) + 2; /* the message's "NAME: " */
            printf("union: cannot be formed: %s\n",
                   strncmp(uerr.msg, rep.name, strlen(rep.name)) == 0 ? uerr.msg + skip : uerr.msg);
        }
        vc_surface_free(&u);
    }
    printf("components: %lld\n", (long long)rep.n_components);
    printf("euler characteristic: %lld\n", (long long)rep.euler);
    if (rep.genus >= 0)
        printf("genus: %lld\n", (long long)rep.genus);
    printf("closed: %s\n", rep.n_boundary_edges == 0 ? "yes" : "no");
    printf("enclosed volume: %.9g%s\n", rep.volume,
           rep.n_boundary_edges ? " (meaningless: surface is open)"
           : rep.signed_volume < 0 ? " (oriented inward)" : "");
    const char *why = solid.coordinate_ratio > VC_SOLID_MAX_COORDINATE_RATIO ? "coordinates too large for the model's size"
                      : solid.n_zero_area ? "zero-area triangles"
                      : solid.n_repeated_same ? "repeated triangles"
                      : solid.n_self_intersections ? "self-intersections"
                      : !closed ? "open"
                      : rep.n_inconsistent_edges ? "inconsistently oriented"
                      : "no enclosed volume";
    if (solid_rc == 0 && closed && !rep.n_inconsistent_edges)
        printf("solid: yes\n");
    else
        printf("solid: no (%s)\n", why);
    if (closed && print_regions(&s) != 0) {
        vc_surface_free(&s);
        return 1;
    }
    /* the named groups of triangles: the mesh's boundary patches */
    if (s.tri_group) {
        printf("groups: %d\n", (int)s.n_groups);
        for (int32_t g = 0; g < s.n_groups; g++) {
            int64_t n = 0;
            for (int64_t t = 0; t < s.n_triangles; t++)
                n += s.tri_group[t] == g;
            printf("group %d: %s, %lld triangles\n", (int)g + 1, s.group_name[g], (long long)n);
        }
    }

    int rc = 0;
    if (features) {
        vc_features f;
        const double scale = max_error > 0 ? max_error * vc_surface_diagonal(&s) : 0;
        if (vc_features_detect_scaled(&s, sharp_angle, NULL, scale, &f, &err)) {
            fprintf(stderr, "vorocrust: %s: %s\n", rep.name, err.msg);
            vc_surface_free(&s);
            return 1;
        }
        printf("sharp angle: %.9g degrees\n", f.sharp_angle);
        printf("sharp edges: %lld (%lld by angle, %lld boundary, %lld non-manifold)\n",
               (long long)f.n_sharp_edges, (long long)f.n_sharp_by_angle, (long long)f.n_boundary_edges,
               (long long)f.n_nonmanifold_edges);
        printf("sharp corners: %lld\n", (long long)f.n_corners);
        printf("noise at the error bound: %lld folds over the sharp angle, %lld corners (not sharp; bound "
               "%.9g)\n",
               (long long)f.n_sharp_noise, (long long)f.n_corner_noise, f.noise_scale);
        printf("folds the error bound sees: %lld below the sharp angle (sharp: their triangles leave "
               "each other's plane by more than %g bounds)\n",
               (long long)f.n_sharp_visible, VC_VISIBLE_FOLD);
        printf("rounds narrower than the error bound: %lld edges in their middle made sharp\n",
               (long long)f.n_sharp_round);
        printf("creases: %lld (%lld open, %lld closed)\n", (long long)f.n_creases,
               (long long)(f.n_creases - f.n_closed_creases), (long long)f.n_closed_creases);
        printf("surface patches: %lld", (long long)f.n_patches);
        if (f.n_nonorientable_patches)
            printf(" (%lld non-orientable)", (long long)f.n_nonorientable_patches);
        printf("\n");
        vc_features_free(&f);
    }
    if (require_closed && vc_surface_require_closed(&rep, &err)) {
        fprintf(stderr, "vorocrust: %s\n", err.msg);
        rc = 1;
    } else if (require_closed && solid_rc) {
        fprintf(stderr, "vorocrust: %s\n", solid_err.msg);
        rc = 1;
    }
    vc_surface_free(&s);
    return rc;
}
