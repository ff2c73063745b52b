/* Consistent orientation of a closed surface whose triangles disagree
 * (an STL exporter's flipped facets): the flips that make every manifold
 * edge walked both ways, each component keeping the orientation most of
 * its triangles have. */
#include "vorocrust/surface.h"
#include "util/small_sort.h"

#include <stdlib.h>
#include <string.h>

typedef struct side_rec {
    int64_t a, b; /* the edge's vertices, a < b */
    int64_t t;    /* the triangle */
    int forward;  /* 1 when t walks a -> b */
} side_rec;

/* (a, b, t, forward): distinct records, so the order is the same for any sort */
#define SIDE_LESS(p, q)                                                                          \
    ((p)->a < (q)->a ||                                                                          \
     ((p)->a == (q)->a && ((p)->b < (q)->b || ((p)->b == (q)->b && ((p)->t < (q)->t ||           \
                                                                    ((p)->t == (q)->t && (p)->forward < (q)->forward))))))
VC_SMALL_SORT(sort_sides, side_rec, SIDE_LESS)

int vc_surface_consistent_flips(const vc_surface *s, unsigned char *flip, int64_t *n_flipped,
                                vc_error *err)
{
    const int64_t nt = s->n_triangles;
    *n_flipped = 0;
    side_rec *e = malloc(sizeof *e * (size_t)(3 * nt + 1));
    /* across[3t + j]: the triangle across side j of t, and whether the two
     * walk that edge the same way (then exactly one of them is flipped) */
    int64_t *across = malloc(sizeof(int64_t) * (size_t)(3 * nt + 1));
    unsigned char *same = malloc((size_t)(3 * nt + 1));
    int64_t *queue = malloc(sizeof(int64_t) * (size_t)(nt + 1));
    unsigned char *seen = calloc((size_t)nt + 1, 1);
    if (!e || !across || !same || !queue || !seen) {
        free(e);
        free(across);
        free(same);
        free(queue);
        free(seen);
        return vc_error_set(err, VC_ENOMEM, "out of memory orienting the surface");
    }
    for (int64_t t = 0; t < nt; t++)
        for (int j = 0; j < 3; j++) {
            const int64_t a = s->tri[3 * t + j], b = s->tri[3 * t + (j + 1) % 3];
            e[3 * t + j] = (side_rec){a < b ? a : b, a < b ? b : a, t, a < b};
            across[3 * t + j] = -1;
        }
    sort_sides(e, 3 * nt);
    for (int64_t k = 0; k < 3 * nt;) {
        int64_t j = k + 1;
        while (j < 3 * nt && e[j].a == e[k].a && e[j].b == e[k].b)
            j++;
        if (j - k == 2) { /* a manifold edge: the only ones that orient */
            for (int i = 0; i < 2; i++) {
                const side_rec *x = &e[k + i], *y = &e[k + 1 - i];
                for (int side = 0; side < 3; side++) {
                    const int64_t p = s->tri[3 * x->t + side], q = s->tri[3 * x->t + (side + 1) % 3];
                    if ((p < q ? p : q) == x->a && (p < q ? q : p) == x->b) {
                        across[3 * x->t + side] = y->t;
                        same[3 * x->t + side] = x->forward == y->forward;
                    }
                }
            }
        }
        k = j;
    }
    free(e);
    int rc = 0;
    for (int64_t root = 0; root < nt && rc == 0; root++) {
        if (seen[root])
            continue;
        /* flood the component from its lowest triangle, then keep the
         * orientation of the majority (the root's on a tie) */
        int64_t head = 0, tail = 0, n_flip = 0;
        seen[root] = 1;
        flip[root] = 0;
        queue[tail++] = root;
        while (head < tail && rc == 0) {
            const int64_t t = queue[head++];
            for (int j = 0; j < 3; j++) {
                const int64_t u = across[3 * t + j];
                if (u < 0)
                    continue;
                const unsigned char want = (unsigned char)(flip[t] ^ same[3 * t + j]);
                if (!seen[u]) {
                    seen[u] = 1;
                    flip[u] = want;
                    queue[tail++] = u;
                } else if (flip[u] != want) {
                    rc = vc_error_set(err, VC_EINPUT,
                                      "the component of triangle %lld cannot be oriented "
                                      "consistently (it is one-sided, like a Moebius strip)",
                                      (long long)root + 1);
                }
            }
        }
        for (int64_t i = 0; i < tail; i++)
            n_flip += flip[queue[i]];
        if (2 * n_flip > tail) {
            for (int64_t i = 0; i < tail; i++)
                flip[queue[i]] ^= 1;
            n_flip = tail - n_flip;
        }
        *n_flipped += n_flip;
    }
    free(across);
    free(same);
    free(queue);
    free(seen);
    return rc;
}

void vc_surface_reverse_triangles(vc_surface *s, const unsigned char *flip)
{
    for (int64_t t = 0; t < s->n_triangles; t++)
        if (flip[t]) {
            const int64_t x = s->tri[3 * t + 1];
            s->tri[3 * t + 1] = s->tri[3 * t + 2];
            s->tri[3 * t + 2] = x;
        }
}
