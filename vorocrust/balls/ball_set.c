#include "balls/ball_set.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define COORD_BITS 19
#define COORD_MAX ((int64_t)1 << COORD_BITS) - 1
/* Each ball is also listed in a coarse cell of its level, 2^COARSE_SHIFT
 * cells wide: a query reaching many cells of a fine level (the Lipschitz
 * bound of a large ball looks 4 radii away for small balls) reads the few
 * coarse cells instead of probing every fine one or reading the whole
 * level. The key's top bit tells coarse keys apart. */
#define COARSE_SHIFT 4
#define COARSE_BIT ((uint64_t)1 << 63)
/* Fine cells a query probes at most before it takes the coarse ones. */
#define FINE_PROBES 512

/* 19 bits per cell coordinate (counted from the origin, clamped) and 6 bits
 * of level: distinct cells have distinct keys. */
static uint64_t cell_key(int level, int64_t i, int64_t j, int64_t k)
{
    return (uint64_t)i | ((uint64_t)j << COORD_BITS) | ((uint64_t)k << (2 * COORD_BITS)) |
           ((uint64_t)level << (3 * COORD_BITS));
}

/* Fibonacci hashing: one multiplication, the table slot and the filter
 * bit taken from the product's high bits (the well-mixed ones). A query
 * hashes every cell it probes (about fifty), and the two rounds of
 * xor-shift and multiply of a full mixer were a fifth of its time. */
static inline uint64_t hash64(uint64_t x) { return x * 0x9E3779B97F4A7C15ull; }

/* The slot of hash h in a table of 2^table_bits slots. */
static inline uint64_t slot_of(const vc_ball_set *bs, uint64_t h) { return h >> (64 - bs->table_bits); }

/* The occupancy filter: one bit per cell key hash (FILTER_BITS per table
 * slot, from the hash's high bits), set when a ball is linked there. A
 * probe of a cell whose bit is clear skips the table: most cells a query
 * probes are empty (balls lie on a surface, the probes fill a box), and
 * the table's head and key loads were most of the sampler's time (memory
 * latency). Unlinking leaves bits set (another key may share them); the
 * filter is rebuilt once as many entries were unlinked as the table has
 * slots. */
#define FILTER_BITS 8
#define FILTER_SHIFT 3 /* log2 of FILTER_BITS */
static uint64_t filter_bit(const vc_ball_set *bs, uint64_t h)
{
    return h >> (64 - bs->table_bits - FILTER_SHIFT);
}

static int filter_has(const vc_ball_set *bs, uint64_t h)
{
    const uint64_t b = filter_bit(bs, h);
    return (int)((bs->filter[b >> 6] >> (b & 63)) & 1);
}

static void filter_set(vc_ball_set *bs, uint64_t h)
{
    const uint64_t b = filter_bit(bs, h);
    bs->filter[b >> 6] |= (uint64_t)1 << (b & 63);
}

/* A clear filter for a table of table_size slots, or NULL. */
static uint64_t *filter_alloc(int64_t table_size)
{
    return calloc((size_t)(FILTER_BITS * table_size / 64), sizeof(uint64_t));
}

/* Replaces the filter by a clear one for the current table size (keeping
 * the old one when out of memory: a superset still). */
static int filter_reset(vc_ball_set *bs)
{
    uint64_t *f = filter_alloc(bs->table_size);
    if (!f)
        return -1;
    free(bs->filter);
    bs->filter = f;
    bs->n_unlinked = 0;
    return 0;
}

static int level_of(const vc_ball_set *bs, double r)
{
    if (!(r > bs->unit))
        return 0;
    int l = (int)floor(log2(r / bs->unit));
    if (l < 0)
        l = 0;
    if (l >= VC_BALL_LEVELS)
        l = VC_BALL_LEVELS - 1;
    return l;
}

/* Cells twice the level's largest radius: a ball reaching a point has its
 * centre within one radius of it, so 2 cells per axis (8 in all) hold every
 * candidate of a point query. */
static double cell_size(const vc_ball_set *bs, int level) { return bs->scale[level + 2]; }

/* The largest radius of a level. */
static double level_radius(const vc_ball_set *bs, int level) { return bs->scale[level + 1]; }

static int64_t cell_coord(double x, double h)
{
    double c = floor(x / h);
    if (c < 0)
        return 0;
    if (c > (double)(COORD_MAX))
        return COORD_MAX;
    return (int64_t)c;
}

/* Empty slots hold this key: no cell has it (the level takes 6 bits, and
 * levels stop at 47). */
#define NO_KEY UINT64_MAX

/* A table of n free slots, or NULL. */
static vc_ball_cell *cells_alloc(int64_t n)
{
    vc_ball_cell *c = malloc(sizeof(vc_ball_cell) * (size_t)n);
    if (!c)
        return NULL;
    for (int64_t i = 0; i < n; i++) {
        c[i].key = NO_KEY;
        c[i].n = c[i].cap = c[i].n_dead = 0;
        c[i].rec = NULL;
    }
    return c;
}

/* The cell of key (hash h), or NULL when it has no slot. */
static vc_ball_cell *find_cell(const vc_ball_set *bs, uint64_t key, uint64_t h)
{
    const uint64_t mask = (uint64_t)bs->table_size - 1;
    for (uint64_t s = slot_of(bs, h);; s = (s + 1) & mask) {
        vc_ball_cell *c = &bs->cell[s];
        if (c->key == key)
            return c;
        if (c->key == NO_KEY)
            return NULL;
    }
}

/* The cell of key, given a slot if it has none (the table has room: see
 * grow). */
static vc_ball_cell *cell_for(vc_ball_set *bs, uint64_t key, uint64_t h)
{
    const uint64_t mask = (uint64_t)bs->table_size - 1;
    for (uint64_t s = slot_of(bs, h);; s = (s + 1) & mask) {
        vc_ball_cell *c = &bs->cell[s];
        if (c->key == key)
            return c;
        if (c->key == NO_KEY) {
            c->key = key;
            bs->n_slots_used++;
            return c;
        }
    }
}

/* The table again at size ts, with the cells that hold balls (their ball
 * lists moved, not copied). Returns 0, or -1 when out of memory (the table
 * unchanged). */
static int rehash(vc_ball_set *bs, int64_t ts)
{
    vc_ball_cell *fresh = cells_alloc(ts);
    uint64_t *f = filter_alloc(ts);
    if (!fresh || !f) {
        free(fresh);
        free(f);
        return -1;
    }
    vc_ball_cell *old = bs->cell;
    const int64_t old_size = bs->table_size;
    bs->cell = fresh;
    bs->table_size = ts;
    bs->table_bits = 0;
    while (((int64_t)1 << bs->table_bits) < ts)
        bs->table_bits++;
    bs->n_slots_used = 0;
    free(bs->filter);
    bs->filter = f;
    bs->n_unlinked = 0;
    for (int64_t i = 0; i < old_size; i++) {
        if (old[i].key == NO_KEY)
            continue;
        if (old[i].n == old[i].n_dead) {
            free(old[i].rec);
            continue;
        }
        const uint64_t h = hash64(old[i].key);
        vc_ball_cell *c = cell_for(bs, old[i].key, h);
        c->n = old[i].n;
        c->n_dead = old[i].n_dead;
        c->cap = old[i].cap;
        c->rec = old[i].rec;
        filter_set(bs, h);
    }
    free(old);
    return 0;
}

int vc_ball_set_init(vc_ball_set *bs, const double lo[3], double diag)
{
    memset(bs, 0, sizeof *bs);
    /* level-0 cells of diag / 2^17: the whole range of 3 diagonals fits in
     * 19 bits per coordinate */
    bs->unit = ldexp(diag > 0 ? diag : 1.0, -18);
    for (int k = 0; k < VC_BALL_LEVELS + 2; k++)
        bs->scale[k] = ldexp(bs->unit, k);
    for (int d = 0; d < 3; d++)
        bs->origin[d] = lo[d] - (diag > 0 ? diag : 1.0);
    bs->table_size = 1 << 12;
    bs->table_bits = 12;
    bs->cell = cells_alloc(bs->table_size);
    if (!bs->cell || filter_reset(bs))
        return -1;
    return 0;
}

void vc_ball_set_free(vc_ball_set *bs)
{
    vc_balls_free(&bs->b);
    for (int64_t i = 0; bs->cell && i < bs->table_size; i++)
        free(bs->cell[i].rec);
    free(bs->cell);
    free(bs->filter);
    free(bs->key);
    free(bs->pos);
    free(bs->level);
    free(bs->level_pos);
    free(bs->changed_reach);
    for (int l = 0; l < VC_BALL_LEVELS; l++)
        free(bs->level_list[l]);
    memset(bs, 0, sizeof *bs);
}

/* Drops the unlinked records of a list, the others keeping their order
 * (and their balls' places updated). */
static void compact(vc_ball_set *bs, vc_ball_cell *c)
{
    const int coarse = (c->key & COARSE_BIT) != 0;
    int32_t m = 0;
    for (int32_t k = 0; k < c->n; k++) {
        if (c->rec[k].id < 0)
            continue;
        c->rec[m] = c->rec[k];
        bs->pos[2 * c->rec[m].id + coarse] = m;
        m++;
    }
    c->n = m;
    c->n_dead = 0;
}

/* Ball i joins the ends of its cell's and its coarse cell's lists (the
 * table has a free slot for each: grow). Returns 0, or -1 when out of
 * memory. */
static int link_ball(vc_ball_set *bs, int64_t i)
{
    for (int64_t e = 2 * i; e <= 2 * i + 1; e++) {
        const uint64_t h = hash64(bs->key[e]);
        vc_ball_cell *c = cell_for(bs, bs->key[e], h);
        if (c->n == c->cap) {
            const int32_t cap = c->cap ? 2 * c->cap : 4;
            vc_ball_rec *q = realloc(c->rec, sizeof(vc_ball_rec) * (size_t)cap);
            if (!q)
                return -1;
            c->rec = q;
            c->cap = cap;
        }
        vc_ball_rec *r = &c->rec[c->n];
        memcpy(r->c, bs->b.center + 3 * i, sizeof r->c);
        r->r = bs->b.radius[i];
        r->id = i;
        bs->pos[e] = c->n++;
        filter_set(bs, h);
    }
    return 0;
}

/* Ball i leaves its two lists: its record is marked unlinked (id -1), and
 * a list is compacted once half of it is such records, so that an unlink
 * costs O(1) on average however many balls a coarse cell holds (a thin
 * shell's: thousands, all moved by the centre lift) and the order of the
 * others is kept. */
static void unlink_ball(vc_ball_set *bs, int64_t i)
{
    for (int64_t e = 2 * i; e <= 2 * i + 1; e++) {
        vc_ball_cell *c = find_cell(bs, bs->key[e], hash64(bs->key[e]));
        c->rec[bs->pos[e]].id = -1;
        c->n_dead++;
        if (c->n_dead == c->n)
            c->n = c->n_dead = 0;
        else if (2 * c->n_dead > c->n)
            compact(bs, c);
    }
    bs->n_unlinked++;
}

/* Ball i's radius in its two lists. */
static void relist_radius(vc_ball_set *bs, int64_t i)
{
    for (int64_t e = 2 * i; e <= 2 * i + 1; e++) {
        vc_ball_cell *c = find_cell(bs, bs->key[e], hash64(bs->key[e]));
        c->rec[bs->pos[e]].r = bs->b.radius[i];
    }
}

/* After many unlinks, the filter again from the cells that hold balls. */
static void filter_refresh(vc_ball_set *bs)
{
    if (bs->n_unlinked < bs->table_size || filter_reset(bs))
        return;
    for (int64_t s = 0; s < bs->table_size; s++)
        if (bs->cell[s].key != NO_KEY && bs->cell[s].n > bs->cell[s].n_dead)
            filter_set(bs, hash64(bs->cell[s].key));
}

static int level_push(vc_ball_set *bs, int l, int64_t i)
{
    if (bs->level_n[l] == bs->level_cap[l]) {
        int64_t c = bs->level_cap[l] ? 2 * bs->level_cap[l] : 64;
        int64_t *q = realloc(bs->level_list[l], sizeof(int64_t) * (size_t)c);
        if (!q)
            return -1;
        bs->level_list[l] = q;
        bs->level_cap[l] = c;
    }
    bs->level_pos[i] = bs->level_n[l];
    bs->level_list[l][bs->level_n[l]++] = i;
    return 0;
}

static void level_remove(vc_ball_set *bs, int l, int64_t i)
{
    int64_t pos = bs->level_pos[i];
    int64_t last = bs->level_list[l][--bs->level_n[l]];
    bs->level_list[l][pos] = last;
    bs->level_pos[last] = pos;
}

static void set_key(vc_ball_set *bs, int64_t i)
{
    int l = bs->level[i];
    double h = cell_size(bs, l);
    const double *c = bs->b.center + 3 * i;
    int64_t x[3];
    for (int d = 0; d < 3; d++)
        x[d] = cell_coord(c[d] - bs->origin[d], h);
    bs->key[2 * i] = cell_key(l, x[0], x[1], x[2]);
    bs->key[2 * i + 1] = cell_key(l, x[0] >> COARSE_SHIFT, x[1] >> COARSE_SHIFT,
                                  x[2] >> COARSE_SHIFT) | COARSE_BIT;
}

/* Orders every list by ball index, the largest last (a query reads a
 * list from its end). The lists are put in this order whenever the ball
 * arrays grow from 4,096 balls on: the order the index always had, so
 * that queries meet balls, and the sampler makes them, as before. */
static int rec_by_id_desc(const void *a, const void *b)
{
    const int64_t x = ((const vc_ball_rec *)a)->id, y = ((const vc_ball_rec *)b)->id;
    return x < y ? 1 : x > y ? -1 : 0;
}

static void order_lists(vc_ball_set *bs)
{
    for (int64_t s = 0; s < bs->table_size; s++) {
        vc_ball_cell *c = &bs->cell[s];
        if (c->key == NO_KEY || c->n == 0)
            continue;
        compact(bs, c);
        qsort(c->rec, (size_t)c->n, sizeof(vc_ball_rec), rec_by_id_desc);
        const int coarse = (c->key & COARSE_BIT) != 0;
        for (int32_t m = 0; m < c->n; m++)
            bs->pos[2 * c->rec[m].id + coarse] = m;
    }
}

/* Room for one more ball. */
static int grow_balls(vc_ball_set *bs)
{
    if (bs->b.n < bs->cap)
        return 0;
    int64_t c = bs->cap ? 2 * bs->cap : 1024;
    vc_balls *b = &bs->b;
#define GROW(ptr, type, k)                                                  \
    do {                                                                    \
        void *q_ = realloc(ptr, sizeof(type) * (size_t)(k) * (size_t)c);    \
        if (!q_)                                                            \
            return -1;                                                      \
        ptr = q_;                                                           \
    } while (0)
    GROW(b->center, double, 3);
    GROW(b->radius, double, 1);
    GROW(b->kind, signed char, 1);
    GROW(b->element, int64_t, 1);
    GROW(b->normal, double, 3);
    GROW(bs->key, uint64_t, 2);
    GROW(bs->pos, int32_t, 2);
    GROW(bs->level, int, 1);
    GROW(bs->level_pos, int64_t, 1);
    GROW(bs->changed_reach, double, 1);
#undef GROW
    bs->cap = c;
    if (c >= 4096)
        order_lists(bs);
    return 0;
}

/* Slots for two more cells with the table at most half full. */
static int table_room(vc_ball_set *bs)
{
    if (2 * (bs->n_slots_used + 2) <= bs->table_size)
        return 0;
    /* four times the cells in use: the slots of emptied cells go */
    int64_t in_use = 0;
    for (int64_t s = 0; s < bs->table_size; s++)
        in_use += bs->cell[s].key != NO_KEY && bs->cell[s].n > bs->cell[s].n_dead;
    int64_t ts = 1 << 12;
    while (ts < 4 * (in_use + 2))
        ts *= 2;
    return rehash(bs, ts);
}

int64_t vc_ball_set_add(vc_ball_set *bs, const double c[3], double r, int kind, int64_t element,
                        const double normal[3])
{
    if (grow_balls(bs) || table_room(bs))
        return -1;
    int64_t i = bs->b.n++;
    vc_balls *b = &bs->b;
    for (int d = 0; d < 3; d++) {
        b->center[3 * i + d] = c[d];
        b->normal[3 * i + d] = normal[d];
    }
    b->radius[i] = r;
    bs->changed_reach[i] = r;
    bs->n_changed++;
    b->kind[i] = (signed char)kind;
    b->element[i] = element;
    bs->level[i] = level_of(bs, r);
    set_key(bs, i);
    if (link_ball(bs, i) || level_push(bs, bs->level[i], i))
        return -1;
    return i;
}

int vc_ball_set_build(vc_ball_set *bs, const vc_balls *b, const double *xyz)
{
    if (!xyz)
        xyz = b->center;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < b->n; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], xyz[3 * i + d] - b->radius[i]);
            hi[d] = fmax(hi[d], xyz[3 * i + d] + b->radius[i]);
        }
    double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (vc_ball_set_init(bs, lo, diag))
        return -1;
    for (int64_t i = 0; i < b->n; i++)
        if (vc_ball_set_add(bs, xyz + 3 * i, b->radius[i], b->kind[i], b->element[i],
                            b->normal + 3 * i) < 0) {
            vc_ball_set_free(bs);
            return -1;
        }
    return 0;
}

void vc_ball_set_forget_changes(vc_ball_set *bs)
{
    if (bs->n_changed > 0)
        memset(bs->changed_reach, 0, sizeof(double) * (size_t)bs->b.n);
    bs->n_changed = 0;
}

int vc_ball_set_resize(vc_ball_set *bs, int64_t i, double r)
{
    if (!(bs->changed_reach[i] > 0))
        bs->n_changed++;
    bs->changed_reach[i] = fmax(bs->changed_reach[i], fmax(bs->b.radius[i], r));
    bs->b.radius[i] = r;
    int l = level_of(bs, r);
    if (l == bs->level[i]) {
        relist_radius(bs, i);
        return 0;
    }
    if (table_room(bs))
        return -1;
    unlink_ball(bs, i);
    filter_refresh(bs);
    level_remove(bs, bs->level[i], i);
    bs->level[i] = l;
    set_key(bs, i);
    if (link_ball(bs, i))
        return -1;
    return level_push(bs, l, i);
}

int vc_ball_set_move(vc_ball_set *bs, int64_t i, const double c[3])
{
    double *p = bs->b.center + 3 * i;
    const double d = sqrt((c[0] - p[0]) * (c[0] - p[0]) + (c[1] - p[1]) * (c[1] - p[1]) +
                          (c[2] - p[2]) * (c[2] - p[2]));
    if (!(bs->changed_reach[i] > 0))
        bs->n_changed++;
    /* what it reached before lies within its radius plus the move of
     * where it is now */
    bs->changed_reach[i] = fmax(bs->changed_reach[i], bs->b.radius[i] + d);
    if (table_room(bs))
        return -1;
    unlink_ball(bs, i);
    filter_refresh(bs);
    memcpy(p, c, sizeof(double) * 3);
    set_key(bs, i);
    return link_ball(bs, i);
}

/* Is a ball of radius r centred at c within reach + radius_factor r of p
 * (to a relative 1e-9 more, and 1e-9 of the cell size h: the rounding of
 * the callers' own tests)? */
static inline int within(const double c[3], double r, const double p[3], double reach,
                         double radius_factor, double h)
{
    const double R = reach + radius_factor * r;
    if (R < 0)
        return 0;
    const double Rs = R * (1 + 1e-9) + 1e-9 * h;
    const double d[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= Rs * Rs;
}

/* fn for the balls of cell c near enough (within), the latest linked
 * first; stops at fn's first non-zero answer and returns it. */
static inline int walk_cell(const vc_ball_cell *c, const double p[3], double reach,
                            double radius_factor, double h, int (*fn)(void *ctx, int64_t i),
                            void *ctx)
{
    for (int32_t m = c ? c->n - 1 : -1; m >= 0; m--) {
        const vc_ball_rec *e = &c->rec[m];
        if (e->id < 0 || !within(e->c, e->r, p, reach, radius_factor, h))
            continue;
        const int r = fn(ctx, e->id);
        if (r)
            return r;
    }
    return 0;
}

int vc_ball_set_query(const vc_ball_set *bs, const double p[3], double reach,
                      double radius_factor, double min_radius, int (*fn)(void *ctx, int64_t i),
                      void *ctx)
{
    /* coarse levels first: the large balls are the likely answer of a
     * covering test, which stops at the first ball found */
    for (int l = VC_BALL_LEVELS - 1; l >= 0; l--) {
        if (bs->level_n[l] == 0)
            continue;
        double h = cell_size(bs, l), rl = level_radius(bs, l);
        if (rl < min_radius)
            break; /* every radius at this level and below is smaller */
        double R = reach + radius_factor * rl; /* radii at this level are below rl */
        if (R < 0)
            continue;
        int64_t lo[3], hi[3];
        double cells = 1;
        for (int d = 0; d < 3; d++) {
            lo[d] = cell_coord(p[d] - bs->origin[d] - R, h);
            hi[d] = cell_coord(p[d] - bs->origin[d] + R, h);
            cells *= (double)(hi[d] - lo[d] + 1);
        }
        int coarse = 0;
        if (cells > FINE_PROBES) {
            double ccells = 1;
            for (int d = 0; d < 3; d++)
                ccells *= (double)((hi[d] >> COARSE_SHIFT) - (lo[d] >> COARSE_SHIFT) + 1);
            coarse = ccells <= (double)bs->level_n[l];
            cells = ccells;
        }
        if (cells > (double)bs->level_n[l]) {
            for (int64_t m = 0; m < bs->level_n[l]; m++) {
                const int64_t i = bs->level_list[l][m];
                if (!within(bs->b.center + 3 * i, bs->b.radius[i], p, reach, radius_factor, h))
                    continue;
                int r = fn(ctx, i);
                if (r)
                    return r;
            }
            continue;
        }
        if (coarse) {
            /* the coarse cells of the range, and in them the balls near
             * enough */
            const int64_t clo[3] = {lo[0] >> COARSE_SHIFT, lo[1] >> COARSE_SHIFT, lo[2] >> COARSE_SHIFT};
            const int64_t chi[3] = {hi[0] >> COARSE_SHIFT, hi[1] >> COARSE_SHIFT, hi[2] >> COARSE_SHIFT};
            for (int64_t i = clo[0]; i <= chi[0]; i++)
                for (int64_t j = clo[1]; j <= chi[1]; j++)
                    for (int64_t k = clo[2]; k <= chi[2]; k++) {
                        const uint64_t key = cell_key(l, i, j, k) | COARSE_BIT;
                        const uint64_t hk = hash64(key);
                        if (!filter_has(bs, hk))
                            continue;
                        const int r = walk_cell(find_cell(bs, key, hk), p, reach, radius_factor,
                                                h, fn, ctx);
                        if (r)
                            return r;
                    }
            continue;
        }
        /* Balls lie on a surface and their radii change slowly along it:
         * near p most levels are empty. The few coarse cells of the range
         * tell that before the fine ones are probed. */
        {
            int any = 0;
            for (int64_t i = lo[0] >> COARSE_SHIFT; i <= hi[0] >> COARSE_SHIFT && !any; i++)
                for (int64_t j = lo[1] >> COARSE_SHIFT; j <= hi[1] >> COARSE_SHIFT && !any; j++)
                    for (int64_t k = lo[2] >> COARSE_SHIFT; k <= hi[2] >> COARSE_SHIFT && !any; k++)
                        any = filter_has(bs, hash64(cell_key(l, i, j, k) | COARSE_BIT));
            if (!any)
                continue;
        }
        /* Per axis, the squared gap from p to each cell of the range: a
         * cell of the box that lies farther than R from p (a corner of the
         * cube around the sphere) holds no centre near enough. Clamped
         * cells (at the grid's ends) are never skipped. */
        double gap2[3][FINE_PROBES];
        for (int d = 0; d < 3; d++)
            for (int64_t c = lo[d]; c <= hi[d]; c++) {
                const double x = p[d] - bs->origin[d], a = (double)c * h, b = a + h;
                const double g = c == 0 || c == COORD_MAX ? 0 : x < a ? a - x : (x > b ? x - b : 0);
                gap2[d][c - lo[d]] = g * g;
            }
        /* with room for the rounding of the cells' bounds and of p - origin */
        const double Rs = R * (1 + 1e-9) + 1e-9 * h, R2 = Rs * Rs;
        for (int64_t i = lo[0]; i <= hi[0]; i++)
            for (int64_t j = lo[1]; j <= hi[1]; j++)
                for (int64_t k = lo[2]; k <= hi[2]; k++) {
                    if (gap2[0][i - lo[0]] + gap2[1][j - lo[1]] + gap2[2][k - lo[2]] > R2)
                        continue;
                    const uint64_t key = cell_key(l, i, j, k);
                    const uint64_t hk = hash64(key);
                    if (!filter_has(bs, hk))
                        continue;
                    const int r = walk_cell(find_cell(bs, key, hk), p, reach, radius_factor, h,
                                            fn, ctx);
                    if (r)
                        return r;
                }
    }
    return 0;
}
