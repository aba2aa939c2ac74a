/* tiles_kernel.h: the tile kernel of tiles.c, compiled once per instruction
 * set. tiles.c includes this file several times, each time defining
 *   TK(name)   the name of this copy's function [name] (a suffix per copy)
 *   TK_TARGET  its target attribute (empty for the portable copy)
 *   TK_W       lanes per vector: 8, 4 or 2 (the tile is TK_W x TK_W)
 *   TK_VD, TK_VI  vector types of TK_W doubles / int64_t
 *   TK_SQRT(p) replace each lane of the TK_VD at p by its correctly rounded
 *              square root
 *   TK_MAX(a, b)  per lane a > b ? a : b (x86's MAXPD: b when either is NaN
 *              or both are zeros), which is py_max(b, a)
 *   TK_ANY(m), TK_ALL(m)  whether some / every lane of the TK_VI mask m
 *              (lanes all ones or all zeros) is set
 *   TK_SPECIALISE  1 to also compile the copies of TILE_SPEC_* (the
 *              common levels, their applier kinds known at compile time)
 * The kernel itself and the reasoning for its order are in tiles.c. The
 * file undefines these parameters at its end, ready for the next copy. */

/* The pair values of row [i] against the lanes j0 .. j0+TK_W-1 (the lane
 * data Xl, Rl, Vl loaded by the caller, with Rnz = Rl != 0, Vnz = Vl != 0),
 * each applier's two masked vectors per element: ga[f][k] for the row's
 * own force (subtracted when the applier pushes apart, added when it pulls
 * together; +0 / -0 where the applier does not act, so the operation leaves
 * the force as it is) and gb[f][k] for the lane's (the other sign, -0 / +0
 * where idle). Returns the appliers that act in some lane (bit f): for the
 * others ga/gb are not written, and leaving them out changes nothing, as
 * every lane would add or subtract its idle zero.
 *
 * [full] (a constant at each call) is the caller's promise that every lane
 * is a partner of the row (valid all set), that the row's and the lanes'
 * radii and values (mass/charge) are all nonzero and that no applier has a
 * max_distance: then !gravity and !electrostatic act in every lane and need
 * no masks, and !collision acts where dist < ra + rb, usually nowhere, in
 * which case it is left out. */
static inline __attribute__((always_inline)) TK_TARGET unsigned
TK(pair_values)(const TileLevel *T, size_t i, TK_VI valid, const TK_VD *Xl,
                TK_VD Rl, TK_VI Rnz, const TK_VD *Vl, const TK_VI *Vnz,
                TK_VD ga[][TILE_MAX_D],
                TK_VD gb[][TILE_MAX_D], const size_t D, const size_t nf,
                const unsigned spec, const bool full)
{
    unsigned acts = 0;
    const TK_VD pz = {0}, nz = -pz;          /* +0 and -0 in every lane */
    TK_VD d[TILE_MAX_D];
    /* sum = 0 + d0*d0 + ...: the first addition is left out, as 0 + x is
     * x for every x but -0, and a square is never -0 */
    d[0] = Xl[0] - T->x[i];
    TK_VD sum = d[0] * d[0];
    for (size_t k = 1; k < D; k++) {
        d[k] = Xl[k] - T->x[k * T->stride + i];
        sum = sum + d[k] * d[k];
    }
    TK_VD dist = sum;
    TK_SQRT(&dist);
    const TK_VD inv = 1 / dist;
    for (size_t k = 0; k < D; k++)
        d[k] = d[k] * inv;                 /* dir = d * inv */
    const double ra = T->rad[i];
    const TK_VD r = ra + Rl;                 /* ra + rb */
    for (size_t f = 0; f < nf; f++) {
        const TileApplier *ap = &T->ap[f];
        const int kind = TILE_KIND(spec, ap, f);
        TK_VI act = valid;
        if (!full && !spec && ap->maxd != 0)
            act = act & (dist < ap->maxd);
        TK_VD k;
        if (kind == TILE_COLLISION) {
            /* ra != 0 and rb != 0 and dist < ra + rb */
            if (full) {
                act = dist < r;
                if (!TK_ANY(act))
                    continue;
            } else {
                act = ra != 0 ? act & Rnz & (dist < r) : (TK_VI){0};
            }
            k = r - dist;
            if (!spec && ap->power != 1) {
                for (size_t l = 0; l < TK_W; l++)
                    if (act[l])
                        k[l] = pow(k[l], ap->power);
            }
            k = k * ap->strength;
        } else {
            /* va != 0 and vb != 0: k = strength*va*vb / (m*m) */
            const double va = T->val[f][i];
            const TK_VD vb = Vl[f];
            const TK_VD m = TK_MAX(dist, r);            /* py_max(r, dist) */
            k = ap->strength * va * vb / (m * m);
            if (full) {
                /* acts in every lane: no masks */
                for (size_t e = 0; e < D; e++)
                    ga[f][e] = gb[f][e] = d[e] * k;
                acts |= 1u << f;
                continue;
            }
            act = va != 0 ? act & Vnz[f] : (TK_VI){0};
        }
        /* the side that subtracts sees +0 when idle, the side that adds
         * sees -0: both leave every value (-0 included) alone */
        const TK_VI idle = ~act & (TK_VI)nz;
        for (size_t e = 0; e < D; e++) {
            TK_VI g = (TK_VI)(d[e] * k);
            TK_VI sub = act & g;
            TK_VI add = sub | idle;
            if (kind == TILE_PULL) {
                ga[f][e] = (TK_VD)add;
                gb[f][e] = (TK_VD)sub;
            } else {
                ga[f][e] = (TK_VD)sub;
                gb[f][e] = (TK_VD)add;
            }
        }
        acts |= 1u << f;
    }
    return acts;
}

/* Doubles one tile's record takes (TK(tile) with rec): a vector for its
 * appliers' bits (the first double), then TK_W partners x nf x D vectors. */
static inline size_t TK(tile_rec)(size_t nf, size_t D)
{
    return (1 + TK_W * nf * D) * TK_W;
}

/* Transpose the TK_W x TK_W matrix whose rows are a[0 .. TK_W-1]: at each
 * stage s (a bit of the row and lane index), rows i and i+s swap their
 * off-diagonal s x s blocks. */
static inline __attribute__((always_inline)) TK_TARGET void
TK(transpose)(TK_VD *a)
{
    for (size_t s = 1; s < TK_W; s *= 2) {
        for (size_t i = 0; i < TK_W; i++) {
            if (i & s)
                continue;
            TK_VD lo, hi;
#if TK_W == 8
            if (s == 1) {
                lo = __builtin_shufflevector(a[i], a[i + s], 0, 8, 2, 10, 4, 12, 6, 14);
                hi = __builtin_shufflevector(a[i], a[i + s], 1, 9, 3, 11, 5, 13, 7, 15);
            } else if (s == 2) {
                lo = __builtin_shufflevector(a[i], a[i + s], 0, 1, 8, 9, 4, 5, 12, 13);
                hi = __builtin_shufflevector(a[i], a[i + s], 2, 3, 10, 11, 6, 7, 14, 15);
            } else {
                lo = __builtin_shufflevector(a[i], a[i + s], 0, 1, 2, 3, 8, 9, 10, 11);
                hi = __builtin_shufflevector(a[i], a[i + s], 4, 5, 6, 7, 12, 13, 14, 15);
            }
#elif TK_W == 4
            if (s == 1) {
                lo = __builtin_shufflevector(a[i], a[i + s], 0, 4, 2, 6);
                hi = __builtin_shufflevector(a[i], a[i + s], 1, 5, 3, 7);
            } else {
                lo = __builtin_shufflevector(a[i], a[i + s], 0, 1, 4, 5);
                hi = __builtin_shufflevector(a[i], a[i + s], 2, 3, 6, 7);
            }
#else
            lo = __builtin_shufflevector(a[i], a[i + s], 0, 2);
            hi = __builtin_shufflevector(a[i], a[i + s], 1, 3);
#endif
            a[i] = lo;
            a[i + s] = hi;
        }
    }
}

/* One tile of row block [i0]: rows i0 .. i0+TK_W-1 against the partners
 * j0 .. j0+TK_W-1 (the diagonal tile when j0 == i0), adding the rows'
 * contributions to the partners' forces in T->F and the partners' to the
 * rows' sums FA (see tiles.c for the order). With [rec] (never a diagonal
 * tile: the split route's FAR part, tiles.c) the partners' contributions
 * to the rows are written to rec instead, TK(tile_rec) doubles: the bits
 * of the appliers that act in the tile, then per partner, applier and
 * element the vector of the rows' values, as TK(replay) adds them.
 * [full]: TK(pair_values). */
static inline __attribute__((always_inline)) TK_TARGET void
TK(tile)(const TileLevel *T, size_t i0, size_t j0, TK_VI lane, TK_VD *FA,
         double *rec, const size_t D, const size_t nf, const unsigned spec,
         const bool full)
{
    const size_t ns = T->stride;
    const TK_VD pz = {0}, nz = -pz;
    const bool diag = j0 == i0;
    TK_VD Xl[TILE_MAX_D], Fb[TILE_MAX_D], Vl[TILE_MAX_F];
    for (size_t k = 0; k < D; k++) {
        memcpy(&Xl[k], T->x + k * ns + j0, sizeof(TK_VD));
        memcpy(&Fb[k], T->F + k * ns + j0, sizeof(TK_VD));
    }
    TK_VD Rl;
    memcpy(&Rl, T->rad + j0, sizeof Rl);
    TK_VI Vnz[TILE_MAX_F];
    for (size_t f = 0; f < nf; f++) {
        memcpy(&Vl[f], T->val[f] + j0, sizeof(TK_VD));
        Vnz[f] = Vl[f] != 0;
    }
    const TK_VI Rnz = Rl != 0;
    const TK_VI inpool = (int64_t)(T->npool - j0) > lane;
    /* the rows' contributions to their own forces, G[f][k][r] (lanes
     * = partners), transposed below to lanes = rows */
    TK_VD G[TILE_MAX_F][TILE_MAX_D][TK_W];
    unsigned tacts = 0;             /* the appliers that act in the tile */
    for (size_t r = 0; r < TK_W; r++) {
        TK_VI valid = diag ? inpool & (lane > (int64_t)r) : inpool;
        if (i0 + r >= T->npart)
            valid = (TK_VI){0};
        /* only the nf x D entries in use are cleared (the whole arrays
         * would be 1.5 KB of stores a row) */
        TK_VD ga[TILE_MAX_F][TILE_MAX_D], gb[TILE_MAX_F][TILE_MAX_D];
        for (size_t f = 0; f < nf; f++)
            for (size_t k = 0; k < D; k++)
                ga[f][k] = gb[f][k] = pz;
        const unsigned acts = TK(pair_values)(T, i0 + r, valid, Xl, Rl, Rnz, Vl,
                                              Vnz, ga, gb, D, nf, spec, full);
        tacts |= acts;
        /* the partners' forces: row after row, applier after applier (an
         * applier that acts in no lane of the row adds nothing) */
        for (size_t f = 0; f < nf; f++) {
            const bool pull = TILE_KIND(spec, &T->ap[f], f) == TILE_PULL;
            for (size_t k = 0; k < D; k++) {
                if (acts >> f & 1) {
                    Fb[k] = pull ? Fb[k] - gb[f][k] : Fb[k] + gb[f][k];
                    G[f][k][r] = ga[f][k];
                } else {
                    G[f][k][r] = pull ? nz : pz;      /* idle */
                }
            }
        }
    }
    for (size_t k = 0; k < D; k++)
        memcpy(T->F + k * ns + j0, &Fb[k], sizeof(TK_VD));
    /* in the diagonal tile the lanes are the rows themselves: every
     * "to" contribution of the block's rows is in now */
    if (diag)
        for (size_t k = 0; k < D; k++)
            FA[k] = Fb[k];
    for (size_t f = 0; f < nf; f++)
        if (tacts >> f & 1)
            for (size_t k = 0; k < D; k++)
                TK(transpose)(G[f][k]);
    if (rec) {
        /* the rows' contributions kept for TK(replay), in the order it
         * adds them: partner, applier, element; only the appliers that
         * act somewhere in the tile (the others would add idle zeros),
         * which the tile's first double says */
        rec[0] = (double)tacts;
        rec += TK_W;
        for (size_t l = 0; l < TK_W; l++)
            for (size_t f = 0; f < nf; f++)
                if (tacts >> f & 1)
                    for (size_t k = 0; k < D; k++)
                        memcpy(rec + ((l * nf + f) * D + k) * TK_W, &G[f][k][l], sizeof(TK_VD));
        return;
    }
    /* the rows' own forces: partner after partner (j ascending),
     * applier after applier (one that acts nowhere in the tile would only
     * add idle zeros) */
    for (size_t l = 0; l < TK_W; l++)
        for (size_t f = 0; f < nf; f++) {
            const bool pull = TILE_KIND(spec, &T->ap[f], f) == TILE_PULL;
            if (!(tacts >> f & 1))
                continue;
            for (size_t k = 0; k < D; k++)
                FA[k] = pull ? FA[k] + G[f][k][l] : FA[k] - G[f][k][l];
        }
}

/* Rows i0 .. i0+TK_W-1 of the reference loop against the partner tiles
 * j0 = jbeg, jbeg+TK_W, ... below jend (tiles.c explains the order); rows
 * at or past npart take no part (all their lanes idle). The rows' own
 * forces are summed as one vector per element, lanes = rows: they start
 * from the diagonal tile when jbeg == i0, else from FAin (D x TK_W, the
 * sums so far), and end in F, or in FAout when not NULL. With [rec] (a
 * block's record on the split route, jbeg past the block's diagonal) each
 * tile goes to its place in rec (TK(tile) with rec) and the rows' sums are
 * neither read nor written. */
static inline __attribute__((always_inline)) TK_TARGET void
TK(row_block)(const TileLevel *T, size_t i0, size_t jbeg, size_t jend,
              const double *FAin, double *FAout, double *rec, const size_t D,
              const size_t nf, const unsigned spec)
{
    const size_t ns = T->stride;
    TK_VD FA[TILE_MAX_D] = {{0}};
    if (jbeg != i0 && !rec)
        for (size_t k = 0; k < D; k++)
            memcpy(&FA[k], FAin + k * TK_W, sizeof(TK_VD));
    TK_VI lane;
    for (size_t l = 0; l < TK_W; l++)
        lane[l] = (int64_t)l;
    /* the fast tiles' promise (TK(pair_values), full): the rows' side */
    bool rows_full = T->fast && i0 + TK_W <= T->npart;
    for (size_t f = 0; f < nf && rows_full; f++)
        for (size_t r = 0; r < TK_W; r++)
            rows_full = rows_full && T->val[f][i0 + r] != 0;
    for (size_t j0 = jbeg; j0 < jend; j0 += TK_W) {
        /* ... and the lanes' side */
        bool full = rows_full && j0 != i0 && j0 + TK_W <= T->npool;
        for (size_t f = 0; f < nf && full; f++) {
            TK_VD v;
            memcpy(&v, T->val[f] + j0, sizeof v);
            full = TK_ALL(v != 0);
        }
        double *trec = rec ? rec + (j0 - jbeg) / TK_W * TK(tile_rec)(nf, D) : NULL;
        if (full)
            TK(tile)(T, i0, j0, lane, FA, trec, D, nf, spec, true);
        else
            TK(tile)(T, i0, j0, lane, FA, trec, D, nf, spec, false);
    }
    if (rec)
        return;
    for (size_t k = 0; k < D; k++) {
        if (FAout)
            memcpy(FAout + k * TK_W, &FA[k], sizeof(TK_VD));
        else
            memcpy(T->F + k * ns + i0, &FA[k], sizeof(TK_VD));
    }
}

/* The rest of row block [i0]'s own forces in the split route (tiles.c):
 * from the sums so far FAin (D x TK_W, the block's rows against the
 * partners below the cut), the contributions the other thread kept in
 * [rec] for the [n] partners from the cut on (TK(tile) with rec), added
 * partner after partner and applier after applier as TK(tile) adds them;
 * the sums end in F. */
static inline __attribute__((always_inline)) TK_TARGET void
TK(replay)(const TileLevel *T, size_t i0, const double *FAin, const double *rec,
           size_t n, const size_t D, const size_t nf, const unsigned spec)
{
    TK_VD FA[TILE_MAX_D];
    for (size_t k = 0; k < D; k++)
        memcpy(&FA[k], FAin + k * TK_W, sizeof(TK_VD));
    for (size_t j = 0; j < n; j += TK_W, rec += TK(tile_rec)(nf, D)) {
        const unsigned tacts = (unsigned)rec[0];
        const double *g0 = rec + TK_W;
        const size_t nl = n - j < TK_W ? n - j : TK_W;
        for (size_t l = 0; l < nl; l++)
            for (size_t f = 0; f < nf; f++) {
                if (!(tacts >> f & 1))
                    continue;
                const bool pull = TILE_KIND(spec, &T->ap[f], f) == TILE_PULL;
                for (size_t k = 0; k < D; k++) {
                    TK_VD g;
                    memcpy(&g, g0 + ((l * nf + f) * D + k) * TK_W, sizeof g);
                    FA[k] = pull ? FA[k] + g : FA[k] - g;
                }
            }
    }
    for (size_t k = 0; k < D; k++)
        memcpy(T->F + k * T->stride + i0, &FA[k], sizeof(TK_VD));
}

/* One row block of one copy (D, nf and spec fixed): what TK(row_block)
 * does, out of line, so the level loop below calls one copy of it. */
typedef void (*TK(RowBlockFn))(const TileLevel *T, size_t i0, size_t jbeg,
                               size_t jend, const double *FAin, double *FAout,
                               double *rec);
/* Its TK(replay), likewise. */
typedef void (*TK(ReplayFn))(const TileLevel *T, size_t i0, const double *FAin,
                             const double *rec, size_t n);

/* The level (TilePart, tiles.c): every row block in order, or (P->wave)
 * the tasks of P's list taken in order until none is left, each once its
 * group's previous task and the previous group's task over the same
 * chunk are done: the group's row blocks in order over the chunk, their
 * row sums handed on through P->buf; or (P->split) one part of the split
 * route with the cut P->cut (a multiple of every width): FAR, the rows
 * below the cut against the partners from it into the record P->rec and
 * then the rows from the cut as on one thread; NEAR, the rows below the
 * cut against the partners below it, their sums into P->buf; REPLAY, the
 * record added onto those sums into F. [rows] runs one row block over a
 * range of partners, [replay] replays one block's record; [nf] is the
 * number of appliers (the record's layout). */
static inline __attribute__((always_inline)) TK_TARGET void
TK(level_run)(const TileLevel *T, TilePart *P, const size_t D,
              const size_t nf, const TK(RowBlockFn) rows,
              const TK(ReplayFn) replay)
{
    if (P->split) {
        /* tiles.c, "Two threads for a middle-sized level": one of its
         * three parts */
        const size_t m = P->cut, n = T->npool - m;
        const size_t per = (n + TK_W - 1) / TK_W * TK(tile_rec)(nf, D);
        switch (P->split) {
        case TILE_SPLIT_FAR:
            for (size_t i0 = 0; i0 < m; i0 += TK_W)
                rows(T, i0, m, T->npool, NULL, NULL, P->rec + i0 / TK_W * per);
            for (size_t i0 = m; i0 < T->npart; i0 += TK_W)
                rows(T, i0, i0, T->npool, NULL, NULL, NULL);
            break;
        case TILE_SPLIT_NEAR:
            for (size_t i0 = 0; i0 < m; i0 += TK_W)
                rows(T, i0, i0, m, NULL, P->buf + i0 * D, NULL);
            break;
        default:
            for (size_t i0 = 0; i0 < m; i0 += TK_W)
                replay(T, i0, P->buf + i0 * D, P->rec + i0 / TK_W * per, n);
            break;
        }
        return;
    }
    if (!P->wave) {
        for (size_t i0 = 0; i0 < T->npart; i0 += TK_W)
            rows(T, i0, i0, T->npool, NULL, NULL, NULL);
        return;
    }
    const size_t R = TILE_GROUP_ROWS / TK_W, nb = (T->npart + TK_W - 1) / TK_W;
    const size_t K = (T->npool + TILE_CHUNK - 1) / TILE_CHUNK;
    for (;;) {
        const size_t t = atomic_fetch_add_explicit(P->next, 1, memory_order_relaxed);
        if (t >= P->ntasks)
            break;
        const TileTask *k = &P->tasks[t];
        if (k->seq)
            tile_wait(&P->prog[k->grp].done, k->seq);
        if (k->above)
            tile_wait(&P->prog[k->grp - 1].done, k->above);
        /* the group's row blocks in order; in the group's first chunk,
         * which holds all their diagonals (tiles.c), each from its own */
        const size_t b1 = (k->grp + 1) * R < nb ? (k->grp + 1) * R : nb;
        const size_t jend = (k->k + 1) * TILE_CHUNK < T->npool ? (k->k + 1) * TILE_CHUNK : T->npool;
        const bool first = k->seq == 0;
        for (size_t b = k->grp * R; b < b1; b++) {
            double *buf = P->buf + b * D * TK_W;
            rows(T, b * TK_W, first ? b * TK_W : k->k * TILE_CHUNK, jend, buf, k->k + 1 == K ? NULL : buf,
                 NULL);
        }
        atomic_store_explicit(&P->prog[k->grp].done, k->seq + 1, memory_order_release);
    }
}

/* A copy of the kernel: its row block (D, nf and the applier description
 * spec known at compile time) and its level loop [name]. */
#define TK_COPY(name, d, f, spec)                                             \
    static TK_TARGET __attribute__((noinline)) void TK(name##_rows)(         \
        const TileLevel *T, size_t i0, size_t jbeg, size_t jend,              \
        const double *FAin, double *FAout, double *rec)                       \
    {                                                                         \
        TK(row_block)(T, i0, jbeg, jend, FAin, FAout, rec, d, f, spec);       \
    }                                                                         \
    static TK_TARGET __attribute__((noinline)) void TK(name##_replay)(       \
        const TileLevel *T, size_t i0, const double *FAin, const double *rec, \
        size_t n)                                                             \
    {                                                                         \
        TK(replay)(T, i0, FAin, rec, n, d, f, spec);                          \
    }                                                                         \
    static TK_TARGET void TK(name)(const TileLevel *T, TilePart *P)          \
    {                                                                         \
        TK(level_run)(T, P, d, f, TK(name##_rows), TK(name##_replay));        \
    }

#define TK_LEVEL(d, f) TK_COPY(level_##d##_##f, d, f, 0)
TK_LEVEL(1, 1) TK_LEVEL(1, 2) TK_LEVEL(1, 3) TK_LEVEL(1, 4)
TK_LEVEL(2, 1) TK_LEVEL(2, 2) TK_LEVEL(2, 3) TK_LEVEL(2, 4)
TK_LEVEL(3, 1) TK_LEVEL(3, 2) TK_LEVEL(3, 3) TK_LEVEL(3, 4)
#undef TK_LEVEL

#if TK_SPECIALISE
/* Copies for the common levels (TILE_SPEC_* in tiles.c), with the kinds of
 * the appliers, power 1 and no max_distance known at compile time. */
#define TK_SPEC_LEVEL(d, si) \
    TK_COPY(spec_##d##_##si, d, TILE_SPEC_NF(si), TILE_SPEC_BITS(si))
#define TK_SPEC_D(d) TK_SPEC_LEVEL(d, 0) TK_SPEC_LEVEL(d, 1) TK_SPEC_LEVEL(d, 2) \
    TK_SPEC_LEVEL(d, 3) TK_SPEC_LEVEL(d, 4) TK_SPEC_LEVEL(d, 5)
TK_SPEC_D(1) TK_SPEC_D(2) TK_SPEC_D(3)
#undef TK_SPEC_D
#undef TK_SPEC_LEVEL
#define TK_SPEC_ROW(d) {TK(spec_##d##_0), TK(spec_##d##_1), TK(spec_##d##_2), \
                        TK(spec_##d##_3), TK(spec_##d##_4), TK(spec_##d##_5)}
#endif
#undef TK_COPY

/* This copy's kernel for D (1..3) and nf (1..4) appliers: its specialised
 * copy [si] (0 .. TILE_NSPECS-1, tile_spec_of()) when it has them, else
 * the general one (si = -1). */
static TK_TARGET void TK(level)(const TileLevel *T, TilePart *P, size_t D, int si)
{
#if TK_SPECIALISE
    static void (*const sp[3][TILE_NSPECS])(const TileLevel *, TilePart *) = {
        TK_SPEC_ROW(1), TK_SPEC_ROW(2), TK_SPEC_ROW(3),
    };
    if (si >= 0) {
        sp[D - 1][si](T, P);
        return;
    }
#undef TK_SPEC_ROW
#else
    (void)si;
#endif
    static void (*const fn[3][4])(const TileLevel *, TilePart *) = {
        {TK(level_1_1), TK(level_1_2), TK(level_1_3), TK(level_1_4)},
        {TK(level_2_1), TK(level_2_2), TK(level_2_3), TK(level_2_4)},
        {TK(level_3_1), TK(level_3_2), TK(level_3_3), TK(level_3_4)},
    };
    fn[D - 1][T->nf - 1](T, P);
}

#undef TK
#undef TK_TARGET
#undef TK_W
#undef TK_VD
#undef TK_VI
#undef TK_SQRT
#undef TK_SPECIALISE
#undef TK_ANY
#undef TK_ALL
#undef TK_MAX
