/* pass_filters.c: `!shader` and the built-in filters and generators
 * (Flitter docs/shaders.md, "!shader" and "Built-in image filters and
 * generators"; their defaults and pass layouts as render/window/shaders.py
 * gives them). Each is a program pass (pass_program.h) with its own
 * template (glsl/NAME.frag), its defaults for the template's names and
 * uniforms, and, for the multi-pass filters, a number of passes and the
 * downsampled ones that depend on how many children it has: with several
 * the first pass composites them, with one the child is read directly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "graph_internal.h"
#include "mem.h"
#include "pass_program.h"
#include "rnode.h"
#include "turns.h"

#define MAX_KW 16

typedef struct FilterKind FilterKind;

/* The frame's parameters of one filter pass: its defaults and pass layout. */
typedef struct Setup {
    Kw kw[MAX_KW];
    size_t nkw;
    ProgramParams pr;
    int dp[4];
} Setup;

struct FilterKind {
    const char *frag;        /* its template (glsl_library name) */
    /* its defaults and passes for node [n] with [nchildren] textures */
    void (*setup)(Graph *g, ProgramPass *pp, const Node *n, size_t nchildren, Setup *s);
};

static void kw_num(Setup *s, const char *name, double x, TplStyle style)
{
    s->kw[s->nkw++] = (Kw){name, {vec_num1(x), style}};
}

static void kw_nums(Setup *s, const char *name, const double *x, uint32_t n)
{
    s->kw[s->nkw++] = (Kw){name, {vec_from_nums(x, n), TPL_LIST}};
}

static void kw_str(Setup *s, const char *name, const char *text)
{
    s->kw[s->nkw++] = (Kw){name, text ? (TplValue){vec_str(text, strlen(text)), TPL_STR} : (TplValue){NULL, TPL_NONE}};
}

/* The passes of a filter whose work takes [work] passes after an optional
 * compositing one, [down] of them downsampled from the [first_down]-th
 * (Flitter: several children 5 passes {1,2,3}, one 4 {0,1,2}, none 1). */
static void layout(Setup *s, size_t nchildren, int work, int first_down, int ndown)
{
    if (nchildren == 0) {
        s->pr.passes = 1;
        return;
    }
    int extra = nchildren > 1 ? 1 : 0;
    s->pr.passes = work + extra;
    for (int i = 0; i < ndown; i++) s->dp[i] = first_down + i + extra;
    s->pr.downsample_passes = s->dp;
    s->pr.ndownsample = (size_t)ndown;
}

/* One string attribute's text of [n] into [out] ([cap] bytes),
 * lower-cased when [lower] (Flitter lower-cases !noise's shape only);
 * false when absent. */
static bool attr_word(Graph *g, const Node *n, const char *name, bool lower, char *out, size_t cap)
{
    Buf b = BUF_INIT;
    bool ok = canvas_attr_str(n, name, g->env.symbols, &b);
    if (ok) {
        snprintf(out, cap, "%s", buf_cstr(&b));
        for (char *c = out; *c && lower; c++)
            if (*c >= 'A' && *c <= 'Z') *c = (char)(*c - 'A' + 'a');
    }
    buf_free(&b);
    return ok;
}

/* {===== the kinds */

static void setup_shader(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n, (void)nc, (void)s;
}

static void setup_adjust(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)pp, (void)nc;
    char tm[32];
    const char *tonemap = NULL;
    if (attr_word(g, n, "tonemap", false, tm, sizeof tm) &&
        (!strcmp(tm, "reinhard") || !strcmp(tm, "aces") || !strcmp(tm, "agx") || !strcmp(tm, "agx_punchy")))
        tonemap = tm;
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    kw_num(s, "exposure", 0, TPL_INT);
    kw_num(s, "contrast", 1, TPL_INT);
    kw_num(s, "brightness", 0, TPL_INT);
    kw_num(s, "shadows", 0, TPL_INT);
    kw_num(s, "highlights", 0, TPL_INT);
    kw_num(s, "hue", 0, TPL_INT);
    kw_num(s, "saturation", 1, TPL_INT);
    kw_nums(s, "color_matrix", identity, 9);
    kw_num(s, "gamma", 1, TPL_INT);
    kw_str(s, "tonemap_function", tonemap);
    kw_num(s, "whitepoint", 0, TPL_INT);
}

static void setup_bloom(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n;
    layout(s, nc, 4, 0, 3);
    s->pr.texel_centres = true;
    kw_num(s, "radius", 0, TPL_INT);
    kw_num(s, "sigma", 0.3, TPL_FLOAT);
    kw_num(s, "exposure", -1, TPL_INT);
    kw_num(s, "contrast", 1, TPL_INT);
    kw_num(s, "brightness", 0, TPL_INT);
    kw_num(s, "shadows", 0, TPL_INT);
    kw_num(s, "highlights", 0, TPL_INT);
    s->pr.clamp = true;
    s->pr.pixel_uniform = "radius";
}

static void setup_blur(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n;
    s->pr.passes = nc > 1 ? 3 : nc ? 2 : 1;
    s->pr.texel_centres = true;
    kw_num(s, "radius", 0, TPL_INT);
    kw_num(s, "sigma", 0.3, TPL_FLOAT);
    s->pr.clamp = true;
    s->pr.pixel_uniform = "radius";
}

static void setup_chromakey(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n;
    layout(s, nc, 4, 0, 3);
    kw_num(s, "radius", 10, TPL_INT);
    kw_num(s, "sigma", 0.3, TPL_FLOAT);
    kw_num(s, "hard", 4, TPL_INT);
    kw_num(s, "hue", 1.0 / 3, TPL_FLOAT);
    kw_num(s, "range", 0.1, TPL_FLOAT);
    kw_num(s, "saturation", 0.75, TPL_FLOAT);
    kw_num(s, "brightness", 0.1, TPL_FLOAT);
    s->pr.clamp = true;
    s->pr.pixel_uniform = "radius";
}

static void setup_edges(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n;
    layout(s, nc, 3, 0, 2);
    kw_num(s, "radius", 0, TPL_INT);
    kw_num(s, "sigma", 0.3, TPL_FLOAT);
    kw_num(s, "mixer", 0, TPL_FLOAT);
    s->pr.clamp = true;
    s->pr.pixel_uniform = "radius";
}

static void setup_feedback(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)n, (void)nc;
    /* no last frame yet: no time has passed for the feedback */
    kw_num(s, "delta", pp->base.target && g->f ? g->f->delta : 0, TPL_FLOAT);
    kw_num(s, "mixer", 0, TPL_INT);
    kw_num(s, "timebase", 1, TPL_INT);
    kw_num(s, "glow", 0, TPL_INT);
    kw_num(s, "translate", 0, TPL_INT);
    kw_num(s, "scale", 1, TPL_INT);
    kw_num(s, "rotate", 0, TPL_INT);
    s->pr.clamp = true;
    s->pr.logical_size = true;
}

static void setup_flare(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n;
    layout(s, nc, 4, 0, 3);
    kw_num(s, "upright_length", 0.25, TPL_FLOAT);
    kw_num(s, "diagonal_length", 0.125, TPL_FLOAT);
    kw_num(s, "ghosts", 6, TPL_INT);
    kw_num(s, "threshold", 1, TPL_INT);
    kw_num(s, "attenuation", 2, TPL_INT);
    kw_num(s, "aberration", 1, TPL_INT);
    kw_num(s, "halo_radius", 0.0625, TPL_FLOAT);
    kw_num(s, "halo_attenuation", 0, TPL_INT);
}

static void setup_kaleid(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)pp, (void)n, (void)nc;
    kw_num(s, "segments", 6, TPL_INT);
    kw_num(s, "rotation", 0, TPL_INT);
    kw_num(s, "radius", 1, TPL_INT);
    s->pr.logical_size = true;
}

static void setup_noise(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)pp, (void)nc;
    char shape[32] = "plane";
    attr_word(g, n, "shape", true, shape, sizeof shape);
    double dflt[4] = {1, 1, 1, 1};
    canvas_attr_nums(n, "default", 4, dflt);
    kw_str(s, "noise_shape", shape);
    kw_num(s, "seed_hash", program_seed_hash(rnode_attr(n, "seed")), TPL_FLOAT);
    kw_nums(s, "default_values", dflt, 4);
    kw_num(s, "components", 1, TPL_INT);
    kw_num(s, "octaves", 1, TPL_INT);
    kw_num(s, "roughness", 0.5, TPL_FLOAT);
    kw_num(s, "origin", 0, TPL_INT);
    kw_num(s, "z", 0, TPL_INT);
    kw_num(s, "scale", 1, TPL_INT);
    kw_num(s, "tscale", 1, TPL_INT);
    kw_num(s, "multiplier", 0.5, TPL_FLOAT);
    kw_num(s, "offset", 0.5, TPL_FLOAT);
    s->pr.logical_size = true;
}

/* 3x3 matrices, column-major as GLSL's mat3 (Flitter's Matrix33). */
static void m3_mul(const double *a, const double *b, double *out)
{
    double r[9];
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) r[c * 3 + k] = a[k] * b[c * 3] + a[3 + k] * b[c * 3 + 1] + a[6 + k] * b[c * 3 + 2];
    memcpy(out, r, sizeof r);
}

static void m3_inverse(const double *m, double *out)
{
    double a = m[0], b = m[3], c = m[6], d = m[1], e = m[4], f = m[7], g = m[2], h = m[5], i = m[8];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    /* the adjugate, column by column (its first column is the first row's cofactors) */
    double adj[9] = {A, B, C, -(b * i - c * h), a * i - c * g, -(a * h - b * g), b * f - c * e, -(a * f - c * d),
                     a * e - b * d};
    for (int k = 0; k < 9; k++) out[k] = adj[k] / det;
}

static void setup_transform(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)g, (void)nc;
    double m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, v[2];
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *key = rnode_attr_name(n, i);
        double step[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        if (strcmp(key, "scale") == 0 && canvas_attr_nums(n, key, 2, v)) {
            step[0] = v[0];
            step[4] = v[1];
        } else if (strcmp(key, "translate") == 0 && canvas_attr_nums(n, key, 2, v)) {
            step[6] = v[0];
            step[7] = v[1];
        } else if (strcmp(key, "rotate") == 0 && canvas_attr_nums(n, key, 1, v)) {
            double c = cos_t(v[0]), sn = sin_t(v[0]);
            step[0] = c;
            step[1] = sn;
            step[3] = -sn;
            step[4] = c;
        } else if (strcmp(key, "keystone") == 0) {
            if (!canvas_attr_nums(n, key, 2, v)) v[0] = v[1] = 0;
            step[2] = v[0] / pp->base.lw;
            step[5] = v[1] / pp->base.lh;
        } else {
            continue;
        }
        m3_mul(m, step, m);   /* the later attribute applies first to the picture */
    }
    double inv[9];
    m3_inverse(m, inv);
    kw_nums(s, "transform_matrix", inv, 9);
    s->pr.logical_size = true;
}

static void setup_vignette(Graph *g, ProgramPass *pp, const Node *n, size_t nc, Setup *s)
{
    (void)pp, (void)nc;
    char fade[32];
    const char *ease = "linear";
    if (attr_word(g, n, "fade", false, fade, sizeof fade) && (!strcmp(fade, "quad") || !strcmp(fade, "cubic")))
        ease = fade;
    kw_num(s, "inset", 0.25, TPL_FLOAT);
    kw_str(s, "ease", ease);
}

/* }===== */

static const FilterKind kinds[] = {
    {"default.frag", setup_shader},   {"adjust.frag", setup_adjust}, {"bloom.frag", setup_bloom},
    {"blur.frag", setup_blur},        {"chromakey.frag", setup_chromakey}, {"edges.frag", setup_edges},
    {"feedback.frag", setup_feedback}, {"flare.frag", setup_flare}, {"kaleid.frag", setup_kaleid},
    {"noise.frag", setup_noise},      {"transform.frag", setup_transform}, {"vignette.frag", setup_vignette},
};

static void update_filter(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    const FilterKind *fk = p->kind->data;
    ProgramPass *pp = (ProgramPass *)p;
    ChildTex kids[32];
    size_t nc = program_children(g, p, kids, 32);
    Setup s;
    memset(&s, 0, sizeof s);
    s.pr.fragment = fk->frag;
    s.pr.children = kids;
    s.pr.nchildren = nc;
    fk->setup(g, pp, n, nc, &s);
    s.pr.kwargs = s.kw;
    s.pr.nkwargs = s.nkw;
    program_render(g, pp, n, cx, &s.pr);
    for (size_t i = 0; i < s.nkw; i++) tpl_value_free(&s.kw[i].value);
}

#define FILTER(NAME, I) \
    {.kind = NAME, .data = &kinds[I], .size = sizeof(ProgramPass), .render = update_filter, \
     .release = program_pass_release}

const PassKind pass_shader = FILTER("shader", 0);
const PassKind pass_filters[] = {
    FILTER("adjust", 1),  FILTER("bloom", 2),  FILTER("blur", 3),   FILTER("chromakey", 4),
    FILTER("edges", 5),   FILTER("feedback", 6), FILTER("flare", 7), FILTER("kaleid", 8),
    FILTER("noise", 9),   FILTER("transform", 10), FILTER("vignette", 11),
};
const size_t pass_nfilters = sizeof pass_filters / sizeof *pass_filters;
