/* pass_program.c: what every shader-program pass shares (see
 * pass_program.h): templates rendered with the node's names, programs
 * compiled once per source text, uniforms set from the node's attributes
 * and the kind's defaults, and Flitter's multi-pass loop
 * (render/window/__init__.py, ProgramNode.render; docs/shaders.md). */
#include "pass_program.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "glsl_library.h"
#include "mem.h"
#include "rnode.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

#define HEADER "#version 330\n"
#define MAX_CHILDREN 32      /* textures one program samples */
#define MAX_PROGRAMS 64      /* programs a graph keeps (the least recently used go; more while one frame uses them) */

/* {===== programs, compiled once per source */

typedef struct Uniform {
    char name[64];           /* without an array's [0] */
    GLenum type;
    GLint size;              /* array length (1 for a plain uniform) */
    GLint loc;
} Uniform;

struct Program {
    char *vsrc, *fsrc;       /* the key */
    uint64_t hash;
    GLuint prog;             /* 0 when it failed */
    char *error;             /* why it failed, or NULL */
    Uniform *uniforms;
    int nuniforms;
    long used;               /* the frame it was last used in */
    bool discards;           /* its fragment source has a `discard` */
};

struct Programs {
    Program **items;
    int n, cap;
};

Programs *programs_new(void) { return mem_calloc(1, sizeof(Programs)); }

static void program_free(Program *p)
{
    if (p->prog) glDeleteProgram(p->prog);
    free(p->vsrc);
    free(p->fsrc);
    free(p->error);
    free(p->uniforms);
    free(p);
}

void programs_free(Programs *ps)
{
    if (!ps) return;
    for (int i = 0; i < ps->n; i++) program_free(ps->items[i]);
    free(ps->items);
    free(ps);
}

static uint64_t text_hash(const char *a, const char *b)
{
    return hash_update(fnv1a_utf8(a, strlen(a)), fnv1a_utf8(b, strlen(b)));
}

/* The first line of GL's log for a shader or program, with "0:LINE(COL)"
 * written as "line LINE". */
static void first_error(const char *log, char *out, size_t cap)
{
    const char *nl = strchr(log, '\n');
    size_t n = nl ? (size_t)(nl - log) : strlen(log);
    int line, col, used = 0;
    if (sscanf(log, "%*d:%d(%d): %n", &line, &col, &used) == 2 && used > 0 && (size_t)used <= n)
        snprintf(out, cap, "line %d: %.*s", line, (int)(n - (size_t)used), log + used);
    else
        snprintf(out, cap, "%.*s", (int)n, log);
}

static GLuint compile(GLenum type, const char *src, Buf *err)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        char first[600];
        first_error(log, first, sizeof first);
        buf_printf(err, "%s shader, %s\n", type == GL_VERTEX_SHADER ? "vertex" : "fragment", first);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

static void reflect(Program *p)
{
    GLint n = 0;
    glGetProgramiv(p->prog, GL_ACTIVE_UNIFORMS, &n);
    p->uniforms = mem_calloc((size_t)(n > 0 ? n : 1), sizeof *p->uniforms);
    for (GLint i = 0; i < n; i++) {
        Uniform *u = &p->uniforms[p->nuniforms];
        char name[128];
        GLsizei len = 0;
        glGetActiveUniform(p->prog, (GLuint)i, sizeof name, &len, &u->size, &u->type, name);
        if (len <= 0 || (size_t)len >= sizeof u->name || (size_t)len >= sizeof name) continue;
        /* uniforms of a block have no location: not settable from attributes */
        u->loc = glGetUniformLocation(p->prog, name);
        if (u->loc < 0) continue;
        char *br = strchr(name, '[');
        if (br) {
            if (strcmp(br, "[0]") != 0) continue;   /* a member of an array of structs */
            *br = '\0';
        }
        if (strchr(name, '.')) continue;            /* a struct's member */
        memcpy(u->name, name, strlen(name) + 1);
        p->nuniforms++;
    }
}

/* The program of sources [vsrc] and [fsrc], compiled now when new (a
 * failure is kept too, so that it is reported and tried once). */
static Program *program_for(Programs *ps, const char *vsrc, const char *fsrc, long frame)
{
    uint64_t h = text_hash(vsrc, fsrc);
    for (int i = 0; i < ps->n; i++) {
        Program *p = ps->items[i];
        if (p->hash == h && strcmp(p->vsrc, vsrc) == 0 && strcmp(p->fsrc, fsrc) == 0) {
            p->used = frame;
            return p;
        }
    }
    if (ps->n >= MAX_PROGRAMS) {
        /* the least recently used goes, never one of this frame's (a pass
         * may hold it while it asks for another) */
        int old = 0;
        for (int i = 1; i < ps->n; i++)
            if (ps->items[i]->used < ps->items[old]->used) old = i;
        if (ps->items[old]->used < frame) {
            program_free(ps->items[old]);
            ps->items[old] = ps->items[--ps->n];
        }
    }
    if (ps->n == ps->cap) {
        ps->cap = ps->cap ? ps->cap * 2 : MAX_PROGRAMS;
        ps->items = mem_realloc(ps->items, (size_t)ps->cap * sizeof *ps->items);
    }
    Program *p = mem_calloc(1, sizeof *p);
    p->vsrc = mem_strdup(vsrc);
    p->fsrc = mem_strdup(fsrc);
    p->discards = strstr(fsrc, "discard") != NULL;
    p->hash = h;
    p->used = frame;
    ps->items[ps->n++] = p;
    Buf err = BUF_INIT;
    GLuint vs = compile(GL_VERTEX_SHADER, vsrc, &err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, fsrc, &err) : 0;
    if (vs && fs) {
        p->prog = glCreateProgram();
        glAttachShader(p->prog, vs);
        glAttachShader(p->prog, fs);
        glBindAttribLocation(p->prog, 0, "position");
        glLinkProgram(p->prog);
        GLint ok = 0;
        glGetProgramiv(p->prog, GL_LINK_STATUS, &ok);
        if (!ok) {
            char log[2048] = "";
            glGetProgramInfoLog(p->prog, sizeof log, NULL, log);
            char first[600];
            first_error(log, first, sizeof first);
            buf_printf(&err, "link: %s\n", first);
            glDeleteProgram(p->prog);
            p->prog = 0;
        }
    }
    if (vs) glDeleteShader(vs);
    if (fs) glDeleteShader(fs);
    if (p->prog) reflect(p);
    else p->error = mem_strdup(buf_line(&err));
    buf_free(&err);
    return p;
}

/* }===== */

/* {===== uniforms from vectors (Flitter's set_uniform_vector) */

typedef enum { U_FLOAT, U_DOUBLE, U_INT, U_UINT, U_BOOL, U_SAMPLER, U_OTHER } UKind;

/* The scalar kind of GL type [t] and its components (a matrix's all). */
static UKind ukind(GLenum t, int *m)
{
    switch (t) {
    case GL_FLOAT: *m = 1; return U_FLOAT;
    case GL_FLOAT_VEC2: *m = 2; return U_FLOAT;
    case GL_FLOAT_VEC3: *m = 3; return U_FLOAT;
    case GL_FLOAT_VEC4: *m = 4; return U_FLOAT;
    case GL_FLOAT_MAT2: *m = 4; return U_FLOAT;
    case GL_FLOAT_MAT3: *m = 9; return U_FLOAT;
    case GL_FLOAT_MAT4: *m = 16; return U_FLOAT;
    case GL_FLOAT_MAT2x3: case GL_FLOAT_MAT3x2: *m = 6; return U_FLOAT;
    case GL_FLOAT_MAT2x4: case GL_FLOAT_MAT4x2: *m = 8; return U_FLOAT;
    case GL_FLOAT_MAT3x4: case GL_FLOAT_MAT4x3: *m = 12; return U_FLOAT;
    case GL_DOUBLE: *m = 1; return U_DOUBLE;
    case GL_DOUBLE_VEC2: *m = 2; return U_DOUBLE;
    case GL_DOUBLE_VEC3: *m = 3; return U_DOUBLE;
    case GL_DOUBLE_VEC4: *m = 4; return U_DOUBLE;
    case GL_DOUBLE_MAT2: *m = 4; return U_DOUBLE;
    case GL_DOUBLE_MAT3: *m = 9; return U_DOUBLE;
    case GL_DOUBLE_MAT4: *m = 16; return U_DOUBLE;
    case GL_INT: *m = 1; return U_INT;
    case GL_INT_VEC2: *m = 2; return U_INT;
    case GL_INT_VEC3: *m = 3; return U_INT;
    case GL_INT_VEC4: *m = 4; return U_INT;
    case GL_UNSIGNED_INT: *m = 1; return U_UINT;
    case GL_UNSIGNED_INT_VEC2: *m = 2; return U_UINT;
    case GL_UNSIGNED_INT_VEC3: *m = 3; return U_UINT;
    case GL_UNSIGNED_INT_VEC4: *m = 4; return U_UINT;
    case GL_BOOL: *m = 1; return U_BOOL;
    case GL_BOOL_VEC2: *m = 2; return U_BOOL;
    case GL_BOOL_VEC3: *m = 3; return U_BOOL;
    case GL_BOOL_VEC4: *m = 4; return U_BOOL;
    case GL_SAMPLER_2D: *m = 1; return U_SAMPLER;
    default: *m = 1; return U_OTHER;
    }
}

/* Upload [need] values [x] to uniform [u]. */
static void upload(const Uniform *u, UKind k, const double *x, int need)
{
    GLsizei n = u->size;
    if (k == U_DOUBLE) {
        switch (u->type) {
        case GL_DOUBLE: glUniform1dv(u->loc, n, x); break;
        case GL_DOUBLE_VEC2: glUniform2dv(u->loc, n, x); break;
        case GL_DOUBLE_VEC3: glUniform3dv(u->loc, n, x); break;
        case GL_DOUBLE_VEC4: glUniform4dv(u->loc, n, x); break;
        case GL_DOUBLE_MAT2: glUniformMatrix2dv(u->loc, n, GL_FALSE, x); break;
        case GL_DOUBLE_MAT3: glUniformMatrix3dv(u->loc, n, GL_FALSE, x); break;
        case GL_DOUBLE_MAT4: glUniformMatrix4dv(u->loc, n, GL_FALSE, x); break;
        default: break;
        }
        return;
    }
    if (k == U_FLOAT) {
        float *f = mem_alloc((size_t)need * sizeof *f);
        for (int i = 0; i < need; i++) f[i] = (float)x[i];
        switch (u->type) {
        case GL_FLOAT: glUniform1fv(u->loc, n, f); break;
        case GL_FLOAT_VEC2: glUniform2fv(u->loc, n, f); break;
        case GL_FLOAT_VEC3: glUniform3fv(u->loc, n, f); break;
        case GL_FLOAT_VEC4: glUniform4fv(u->loc, n, f); break;
        case GL_FLOAT_MAT2: glUniformMatrix2fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT3: glUniformMatrix3fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT4: glUniformMatrix4fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT2x3: glUniformMatrix2x3fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT3x2: glUniformMatrix3x2fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT2x4: glUniformMatrix2x4fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT4x2: glUniformMatrix4x2fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT3x4: glUniformMatrix3x4fv(u->loc, n, GL_FALSE, f); break;
        case GL_FLOAT_MAT4x3: glUniformMatrix4x3fv(u->loc, n, GL_FALSE, f); break;
        default: break;
        }
        free(f);
        return;
    }
    if (k == U_UINT) {
        GLuint *v = mem_alloc((size_t)need * sizeof *v);
        for (int i = 0; i < need; i++) v[i] = x[i] <= 0 ? 0 : x[i] >= 4294967295.0 ? 0xffffffffu : (GLuint)x[i];
        switch (u->type) {
        case GL_UNSIGNED_INT: glUniform1uiv(u->loc, n, v); break;
        case GL_UNSIGNED_INT_VEC2: glUniform2uiv(u->loc, n, v); break;
        case GL_UNSIGNED_INT_VEC3: glUniform3uiv(u->loc, n, v); break;
        default: glUniform4uiv(u->loc, n, v); break;
        }
        free(v);
        return;
    }
    GLint *v = mem_alloc((size_t)need * sizeof *v);
    for (int i = 0; i < need; i++)
        v[i] = k == U_BOOL ? x[i] != 0 : x[i] <= -2147483648.0 ? INT32_MIN : x[i] >= 2147483647.0 ? INT32_MAX : (GLint)x[i];
    switch (u->type) {
    case GL_INT: case GL_BOOL: glUniform1iv(u->loc, n, v); break;
    case GL_INT_VEC2: case GL_BOOL_VEC2: glUniform2iv(u->loc, n, v); break;
    case GL_INT_VEC3: case GL_BOOL_VEC3: glUniform3iv(u->loc, n, v); break;
    default: glUniform4iv(u->loc, n, v); break;
    }
    free(v);
}

/* Set uniform [u] from vector [v] as Flitter's set_uniform_vector does:
 * numbers only (an int uniform takes no symbol), array length times
 * components of them, or one number for all, or (an array of vectors) one
 * vector for each, each number times [times] (a measure in pixels at the
 * frame's scale; 1: as given); ints floored. False, setting nothing,
 * otherwise. */
static bool set_from_vector(const Uniform *u, const Vec *v, const SymTab *st, double times)
{
    int m;
    UKind k = ukind(u->type, &m);
    if (k == U_SAMPLER || k == U_OTHER || !vec_is_num(v) || vec_len(v) == 0) return false;
    int n = u->size, need = n * m;
    uint32_t len = vec_len(v);
    const double *x = vec_cnums(v);
    bool whole = (uint32_t)need == len, one = len == 1, each = n > 1 && m > 1 && len == (uint32_t)m;
    if (!whole && !one && !each) return false;
    bool integral = k == U_INT || k == U_UINT || k == U_BOOL;
    double *vals = mem_alloc((size_t)need * sizeof *vals);
    bool ok = true;
    for (int i = 0; i < need && ok; i++) {
        double y = x[whole ? i : one ? 0 : i % m];
        if (times != 1 && !(st && symtab_name(st, y))) y *= times;
        if (integral) {
            /* Vector.match(n, int) refuses symbols and floors */
            if (st && symtab_name(st, y)) ok = false;
            y = floor(y);
        }
        vals[i] = y;
    }
    if (ok) upload(u, k, vals, need);
    free(vals);
    return ok;
}

static void set_number(const Uniform *u, double x)
{
    int m;
    UKind k = ukind(u->type, &m);
    if (k == U_SAMPLER || k == U_OTHER) return;
    int need = u->size * m;
    double *vals = mem_alloc((size_t)need * sizeof *vals);
    for (int i = 0; i < need; i++) vals[i] = x;
    upload(u, k, vals, need);
    free(vals);
}

static void set_pair(const Uniform *u, double a, double b)
{
    int m;
    UKind k = ukind(u->type, &m);
    if (k == U_SAMPLER || k == U_OTHER || m != 2 || u->size != 1) {
        set_number(u, a);
        return;
    }
    double v[2] = {a, b};
    upload(u, k, v, 2);
}

/* }===== */

/* {===== template names */

static const char *const reserved[] = {"fragment", "vertex", "loop", "context", "UNDEFINED"};

/* What setting a program's uniforms needs: the pass's node, its kind's
 * defaults, the textures it samples (on units 1.. in order) and its pass
 * count. */
typedef struct ProgramUse {
    Graph *g;
    const Node *n;
    const ProgramParams *pr;
    const ChildTex *children;
    size_t nchildren;
    int passes;
} ProgramUse;

/* A template's names: the pass's, and its composite= as text. */
typedef struct Names {
    ProgramUse use;
    const char *composite;
} Names;

static bool is_reserved(const char *name, size_t len)
{
    for (size_t i = 0; i < sizeof reserved / sizeof *reserved; i++)
        if (strlen(reserved[i]) == len && memcmp(reserved[i], name, len) == 0) return true;
    return false;
}

/* The default [name] of [pr] (borrowed), or NULL. */
static const Kw *kw_find(const ProgramParams *pr, const char *name, size_t len)
{
    for (size_t i = 0; i < pr->nkwargs; i++)
        if (strlen(pr->kwargs[i].name) == len && memcmp(pr->kwargs[i].name, name, len) == 0) return &pr->kwargs[i];
    return NULL;
}

/* A template name: HEADER, child_textures, the node's attributes, then
 * the defaults (passes, composite, the kind's, the engine's names and
 * defines), as Flitter's get_fragment_source builds its names. */
static bool lookup_name(void *ctx, const char *name, size_t len, TplValue *out)
{
    const Names *names = ctx;
    const ProgramUse *N = &names->use;
#define IS(s) (len == sizeof s - 1 && memcmp(name, s, sizeof s - 1) == 0)
    if (IS("HEADER")) {
        *out = (TplValue){vec_str(HEADER, strlen(HEADER)), TPL_STR};
        return true;
    }
    if (IS("child_textures")) {
        Vec *parts[MAX_CHILDREN];
        for (size_t i = 0; i < N->nchildren; i++) parts[i] = vec_str(N->children[i].name, strlen(N->children[i].name));
        *out = (TplValue){vec_compose_take(parts, N->nchildren), TPL_LIST};
        return true;
    }
    /* the node's attributes and the engine's names are copied, never
     * shared: a template's values are then the graph's own, whose counts
     * no other thread changes (fl_picture_draw) */
    if (!is_reserved(name, len)) {
        const Vec *v = node_attr_n(N->n, name, len);
        if (v) {
            *out = (TplValue){vec_copy_deep(v), TPL_VEC};
            return true;
        }
    }
    if (IS("passes")) {
        *out = (TplValue){vec_num1(N->passes), TPL_INT};
        return true;
    }
    if (IS("composite")) {
        *out = (TplValue){vec_str(names->composite, strlen(names->composite)), TPL_STR};
        return true;
    }
#undef IS
    const Kw *kw = kw_find(N->pr, name, len);
    if (kw) {
        *out = (TplValue){vec_share(kw->value.v), kw->value.style};
        return true;
    }
    const GraphFrame *f = N->g->f;
    const Vec *v = f && f->name ? f->name(f->ctx, name, len) : NULL;
    if (v) {
        *out = (TplValue){vec_copy_deep(v), TPL_VEC};
        return true;
    }
    return false;
}

/* }===== */

/* {===== the pass */

size_t program_children(Graph *g, Pass *p, ChildTex *out, size_t cap)
{
    size_t k = 0;
    for (size_t i = 0; i < p->nchildren && k < cap; i++) {
        Pass *c = p->children[i];
        int w, h;
        GLuint tex = graph_pass_texture(g, c, &w, &h);
        if (!tex || c->hidden) continue;
        snprintf(out[k].name, sizeof out[k].name, "texture%u", (unsigned)k);
        out[k].tex = tex;
        out[k].w = w;
        out[k].h = h;
        k++;
    }
    return k;
}

void program_pass_release(Graph *g, Pass *p)
{
    (void)g;
    ProgramPass *pp = (ProgramPass *)p;
    buf_free(&pp->vsrc);
    buf_free(&pp->fsrc);
    buf_free(&pp->good_vsrc);
    buf_free(&pp->good_fsrc);
    pp->program = NULL;
}

/* One string attribute's text into [out]; false when absent. */
static bool attr_text(Graph *g, const Node *n, const char *name, Buf *out)
{
    const Vec *v = rnode_attr(n, name);
    if (!v) return false;
    buf_reset(out);
    fmt_str(out, v, g->env.symbols);
    return true;
}

/* One whole number of attribute [name] (Flitter node.get(name, 1, int)),
 * or [dflt]. */
static int attr_int(const Node *n, const char *name, int dflt, const SymTab *st)
{
    const Vec *v = rnode_attr(n, name);
    if (!vec_is_num(v) || vec_len(v) != 1) return dflt;
    double x = vec_cnums(v)[0];
    if ((st && symtab_name(st, x)) || !(x > -1e9 && x < 1e9)) return dflt;
    return (int)floor(x);
}

/* Render the template [name] of the kind or the node's [attr] into [out]. */
static bool render_source(Graph *g, ProgramPass *pp, const Node *n, const char *attr, const char *dflt, Names *N,
                          Buf *out)
{
    Buf src = BUF_INIT;
    const char *text;
    size_t len;
    if (attr_text(g, n, attr, &src)) {
        text = src.data ? src.data : "";
        len = src.len;
    } else {
        text = glsl_library(dflt);
        len = text ? strlen(text) : 0;
    }
    TplEnv env = {.lookup = lookup_name, .ctx = N, .include = glsl_library, .symbols = g->env.symbols};
    buf_reset(out);
    Buf err = BUF_INIT;
    int rc = text ? tpl_render(text, len, &env, out, &err) : -1;
    if (!text) buf_printf(&err, "no template %s\n", dflt);
    buf_free(&src);
    if (rc != 0) {
        graph_note(g, RLOG_ERROR, "%s: !%s%s%s: %s template, %s", g->f && g->f->script ? g->f->script : "script",
                   pp->base.kind->kind, pp->base.has_id ? " id=" : "",
                   pp->base.has_id ? buf_cstr(&pp->base.id) : "", attr, buf_line(&err));
        buf_free(&err);
        return false;
    }
    /* a trailing newline keeps line numbers of errors, as Flitter strips the text */
    while (out->len && (out->data[out->len - 1] == '\n' || out->data[out->len - 1] == ' ')) out->data[--out->len] = '\0';
    buf_putc(out, '\n');
    return true;
}

static bool is_downsampled(const ProgramParams *pr, const int *dp, size_t ndp, int pass)
{
    (void)pr;
    for (size_t i = 0; i < ndp; i++)
        if (dp[i] == pass) return true;
    return false;
}

/* The sampler settings of a pass: border colour or repeats, nearest. */
typedef struct Sampling {
    GLint wrap_s, wrap_t;
    float border[4];
    GLint filter;
} Sampling;

static void sampling_of(Graph *g, const Node *n, const ProgramParams *pr, Sampling *s)
{
    (void)g;
    double v[4];
    *s = (Sampling){GL_CLAMP_TO_BORDER, GL_CLAMP_TO_BORDER, {0, 0, 0, 0}, GL_LINEAR};
    if (pr->clamp) s->wrap_s = s->wrap_t = GL_CLAMP_TO_EDGE;
    if (canvas_attr_nums(n, "border", 4, v)) {
        s->wrap_s = s->wrap_t = GL_CLAMP_TO_BORDER;
        for (int k = 0; k < 4; k++) s->border[k] = (float)v[k];
    } else if (rnode_attr(n, "repeat") && vec_is_num(rnode_attr(n, "repeat")) &&
               (vec_len(rnode_attr(n, "repeat")) == 2 || vec_len(rnode_attr(n, "repeat")) == 1)) {
        const Vec *r = rnode_attr(n, "repeat");
        bool rx = vec_cnums(r)[0] != 0, ry = vec_cnums(r)[vec_len(r) - 1] != 0;
        s->wrap_s = rx ? GL_REPEAT : GL_CLAMP_TO_EDGE;
        s->wrap_t = ry ? GL_REPEAT : GL_CLAMP_TO_EDGE;
    }
    const Vec *nearest = rnode_attr(n, "nearest");
    if (nearest && vec_truthy(nearest)) s->filter = GL_NEAREST;
}

static GLuint make_sampler(const Sampling *s)
{
    GLuint sm;
    glGenSamplers(1, &sm);
    glSamplerParameteri(sm, GL_TEXTURE_WRAP_S, s->wrap_s);
    glSamplerParameteri(sm, GL_TEXTURE_WRAP_T, s->wrap_t);
    glSamplerParameteri(sm, GL_TEXTURE_MIN_FILTER, s->filter);
    glSamplerParameteri(sm, GL_TEXTURE_MAG_FILTER, s->filter);
    glSamplerParameterfv(sm, GL_TEXTURE_BORDER_COLOR, s->border);
    return sm;
}

static void bind_unit(int unit, GLuint tex, GLuint sampler)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_2D, tex);
    glBindSampler((GLuint)unit, sampler);
}

/* The uniform [name] of [pg], or NULL when it has none (active). */
static const Uniform *find_uniform(const Program *pg, const char *name)
{
    for (int i = 0; i < pg->nuniforms; i++)
        if (strcmp(pg->uniforms[i].name, name) == 0) return &pg->uniforms[i];
    return NULL;
}

/* The uniforms set again for each pass. */
typedef struct Uniforms {
    const Uniform *last, *first, *pass, *size, *down;
} Uniforms;

/* Set every uniform of [pg] (current) but those of each pass, which go
 * into [un]: from the node's attributes, then the kind's defaults, then
 * the engine's names, else Flitter's rule (a name within 'alpha' is 1,
 * anything else 0); samplers to their textures' units. */
static void set_uniforms(const ProgramUse *pu, const Program *pg, Uniforms *un)
{
    const SymTab *st = pu->g->env.symbols;
    *un = (Uniforms){0};
    for (int i = 0; i < pg->nuniforms; i++) {
        const Uniform *u = &pg->uniforms[i];
        const char *name = u->name;
        int m;
        UKind k = ukind(u->type, &m);
        if (strcmp(name, "last") == 0) {
            un->last = u;
        } else if (strcmp(name, "first") == 0) {
            un->first = u;
        } else if (strcmp(name, "pass") == 0) {
            un->pass = u;
        } else if (strcmp(name, "size") == 0) {
            un->size = u;
        } else if (strcmp(name, "downsample") == 0) {
            un->down = u;
        } else if (strcmp(name, "passes") == 0 && !rnode_attr(pu->n, "passes")) {
            set_number(u, pu->passes);
        } else if (k == U_SAMPLER) {
            int unit = 0;
            for (size_t c = 0; c < pu->nchildren && c + 1 < 30; c++)
                if (strcmp(pu->children[c].name, name) == 0) unit = (int)c + 1;
            glUniform1i(u->loc, unit);
        } else {
            const Vec *attr = is_reserved(name, strlen(name)) ? NULL : rnode_attr(pu->n, name);
            const Kw *kw = kw_find(pu->pr, name, strlen(name));
            const GraphFrame *f = pu->g->f;
            const Vec *eng = !kw && f && f->name ? f->name(f->ctx, name, strlen(name)) : NULL;
            /* a measure in pixels at the frame's scale */
            double k = pu->pr->pixel_uniform && strcmp(name, pu->pr->pixel_uniform) == 0 ? pu->g->draw_scale : 1;
            if (attr && set_from_vector(u, attr, st, k)) continue;
            if (kw && set_from_vector(u, kw->value.v, st, k)) continue;
            if (eng && set_from_vector(u, eng, st, 1)) continue;
            /* Flitter: `name in 'alpha'` (a substring of it) is 1, anything else 0 */
            set_number(u, strstr("alpha", name) ? 1 : 0);
        }
    }
}

/* [prog] with its fragment's `uniform int pass;` made the constant
 * [pass] (one program per pass of a multi-pass program); [prog] itself
 * when its fragment does not declare it so or the variant fails. */
static Program *pass_program(Graph *g, Program *prog, int pass)
{
    static const char decl[] = "uniform int pass;";
    const char *at = strstr(prog->fsrc, decl);
    if (!at) return prog;
    Buf src = BUF_INIT;
    buf_add(&src, prog->fsrc, (size_t)(at - prog->fsrc));
    buf_printf(&src, "const int pass = %d;", pass);
    buf_puts(&src, at + sizeof decl - 1);
    Program *v = program_for(g->programs, prog->vsrc, buf_cstr(&src), g->frame);
    buf_free(&src);
    return v->prog ? v : prog;
}

/* The one child of [p] whose picture it would draw (not hidden, with a
 * texture), or NULL when there are none or several. */
static Pass *sole_child(Graph *g, Pass *p)
{
    Pass *one = NULL;
    for (size_t i = 0; i < p->nchildren; i++) {
        Pass *c = p->children[i];
        int w, h;
        if (c->hidden || !graph_pass_texture(g, c, &w, &h)) continue;
        if (one) return NULL;
        one = c;
    }
    return one;
}

/* A program pass that would only copy its one child's picture: the
 * default programs of a !window, !offscreen or !record ([pr]->pass_through)
 * with no attribute that changes the picture (fragment=, vertex=, alpha=,
 * passes=), one child of the same size whose framebuffer nothing else
 * keeps (no id, no `last`), and of the pass's own format when
 * [pr]->keep_format (a !record writing its file, a window given
 * colorbits=; otherwise the picture's light passes up at its child's
 * precision, not quantised again).
 * Over nothing, the default program's output is its input texel for
 * texel, so the child's framebuffer is taken over as the pass's picture
 * instead of drawing it again (on a CPU rasteriser a full-size pass is
 * dear: bench/PROFILE.md, "lib/render/gl/pass_program.c: a pass that only
 * copies its child"). Returns whether it did. */
static bool pass_through(Graph *g, Pass *p, const Node *n, const ProgramParams *pr, int colorbits)
{
    if (!pr->pass_through || rnode_attr(n, "fragment") || rnode_attr(n, "vertex") || rnode_attr(n, "passes") ||
        rnode_attr(n, "downsample_passes"))
        return false;
    const Vec *a = rnode_attr(n, "alpha");
    if (a && !(vec_is_scalar(a) && vec_scalar(a) == 1)) return false;
    Pass *c = sole_child(g, p);
    if (!c || c->kind->texture || !c->target || c->retain || c->has_id || c->busy) return false;
    GlTarget *t = c->target;
    if (t->w != p->w || t->h != p->h || t->samples) return false;
    if (pr->keep_format && (t->colorbits != colorbits || t->srgb != (pr->srgb && colorbits == 8))) return false;
    if (p->target) target_release(g->pool, p->target);
    p->target = t;
    c->target = NULL;
    return true;
}

void program_render(Graph *g, ProgramPass *pp, const Node *n, const PassCtx *cx, const ProgramParams *pr)
{
    Pass *p = &pp->base;
    const SymTab *st = g->env.symbols;
    ChildTex kids[MAX_CHILDREN];
    const ChildTex *children = pr->children;
    size_t nchildren = pr->nchildren;
    if (!children) {
        nchildren = program_children(g, p, kids, MAX_CHILDREN);
        children = kids;
    }
    /* composite= (or blend=), passes=, downsample=, downsample_passes=, colorbits= */
    Buf composite = BUF_INIT;
    if (!attr_text(g, n, "composite", &composite) && !attr_text(g, n, "blend", &composite))
        buf_puts(&composite, "over");
    int passes = attr_int(n, "passes", pr->passes > 0 ? pr->passes : 1, st);
    if (passes < 1) passes = 1;
    if (passes > 64) passes = 64;
    int downsample = attr_int(n, "downsample", pr->downsample > 0 ? pr->downsample : 2, st);
    if (downsample < 1) downsample = 1;
    int dps[64];
    const int *dp = pr->downsample_passes;
    size_t ndp = pr->ndownsample;
    const Vec *dpv = rnode_attr(n, "downsample_passes");
    if (vec_is_num(dpv)) {
        ndp = 0;
        for (uint32_t i = 0; i < vec_len(dpv) && ndp < 64; i++) dps[ndp++] = (int)floor(vec_cnums(dpv)[i]);
        dp = dps;
    }
    int colorbits = pr->colorbits ? pr->colorbits : attr_int(n, "colorbits", cx->colorbits, st);
    if (colorbits != 8 && colorbits != 16 && colorbits != 32) colorbits = cx->colorbits;
    if (pass_through(g, p, n, pr, colorbits)) {
        buf_free(&composite);
        p->retain = p->has_id;
        return;
    }
    /* the sources of this frame, and their program */
    Names N = {{g, n, pr, children, nchildren, passes}, buf_cstr(&composite)};
    Program *prog = NULL;
    if (render_source(g, pp, n, "vertex", pr->vertex ? pr->vertex : "default.vert", &N, &pp->vsrc) &&
        render_source(g, pp, n, "fragment", pr->fragment ? pr->fragment : "default.frag", &N, &pp->fsrc)) {
        prog = program_for(g->programs, buf_cstr(&pp->vsrc), buf_cstr(&pp->fsrc), g->frame);
        if (!prog->prog) {
            graph_note(g, RLOG_ERROR, "%s: !%s%s%s: GLSL error: %s", g->f && g->f->script ? g->f->script : "script",
                       p->kind->kind, p->has_id ? " id=" : "", p->has_id ? buf_cstr(&p->id) : "", prog->error);
            prog = NULL;
        }
    }
    if (prog) {
        /* the sources of the pass's last good program */
        if (!pp->good_fsrc.len || strcmp(pp->good_fsrc.data, buf_cstr(&pp->fsrc)) != 0 ||
            strcmp(buf_cstr(&pp->good_vsrc), buf_cstr(&pp->vsrc)) != 0) {
            buf_reset(&pp->good_vsrc);
            buf_puts(&pp->good_vsrc, buf_cstr(&pp->vsrc));
            buf_reset(&pp->good_fsrc);
            buf_puts(&pp->good_fsrc, buf_cstr(&pp->fsrc));
        }
    } else if (pp->good_fsrc.len) {
        /* a shader edited into an error (or a template that fails now)
         * keeps drawing with the last program that compiled, as a
         * script that fails to load keeps the last one running; the
         * error is logged above */
        Program *good = program_for(g->programs, buf_cstr(&pp->good_vsrc), buf_cstr(&pp->good_fsrc), g->frame);
        if (good->prog) prog = good;
    }
    buf_free(&composite);
    pp->program = prog;
    if (!prog) return;   /* no output (a pass that keeps its target keeps its last picture) */
    /* the samplers: the children on units 1.. in order, then last and
     * first; unit 0 the zero texture (a sampler with nothing bound) */
    Sampling smp;
    sampling_of(g, n, pr, &smp);
    GLuint sampler = make_sampler(&smp);
    /* (pr->texel_centres: the same sampling, nearest, for the textures
     * of each pass's size) */
    bool own_template = !rnode_attr(n, "fragment") && !rnode_attr(n, "vertex");
    GLuint centres = 0;
    if (pr->texel_centres && smp.filter == GL_LINEAR && own_template) {
        Sampling nearest = smp;
        nearest.filter = GL_NEAREST;
        centres = make_sampler(&nearest);
    }
    bind_unit(0, g->zero_tex, 0);
    int nunits = 1;
    for (size_t c = 0; c < nchildren && nunits < 30; c++) bind_unit(nunits++, children[c].tex, sampler);
    int last_unit = nunits, first_unit = nunits + 1;
    ProgramUse use = N.use;
    /* with several passes and `uniform int pass;` in the fragment
     * template, each pass draws with a program of its own where `pass` is
     * that pass's constant: the same picture, and a CPU rasteriser, which
     * runs every branch of a shader, then runs only that pass's */
    bool specialise = passes > 1 && find_uniform(prog, "pass") && !strstr(prog->vsrc, "pass");
    /* the framebuffer is kept for the next frame when its first pass
     * reads `last` (the frame before's picture: Flitter keeps it whenever
     * the program has `last`, which a multi-pass filter such as !bloom
     * reads only within the frame), or an id names it */
    bool retain = p->has_id || find_uniform(specialise ? pass_program(g, prog, 0) : prog, "last");
    Program *current = NULL;
    Uniforms un = {0};
    p->retain = retain;
    /* Flitter blends each pass's quad `over` (ONE, ONE_MINUS_SRC_ALPHA)
     * into its target, cleared to transparent just before: over nothing
     * that is the quad's colour itself, so blending is left off (on a CPU
     * rasteriser it would read the target back for nothing) */
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    GlTarget *last = p->target, *first = NULL;
    p->target = NULL;
    bool failed = false;
    for (int pass = 0; pass < passes; pass++) {
        Program *pg = specialise ? pass_program(g, prog, pass) : prog;
        if (pg != current) {
            glUseProgram(pg->prog);
            set_uniforms(&use, pg, &un);
            current = pg;
        }
        if (un.pass) set_number(un.pass, pass);
        if (un.last) {
            if (last) bind_unit(last_unit, last->tex, sampler);
            glUniform1i(un.last->loc, last ? last_unit : 0);
        }
        if (un.first) {
            if (pass >= 1 && first) bind_unit(first_unit, first->tex, sampler);
            glUniform1i(un.first->loc, pass >= 1 && first ? first_unit : 0);
        }
        bool down = is_downsampled(pr, dp, ndp, pass);
        int w = down ? p->w / downsample : p->w, h = down ? p->h / downsample : p->h;
        if (un.down) set_number(un.down, down ? downsample : 1);
        GlTarget *t = graph_target(g, w < 1 ? 1 : w, h < 1 ? 1 : h, colorbits, pr->srgb, false, 0);
        if (!t) {
            failed = true;
            break;
        }
        if (un.size) {
            if (pr->logical_size && (p->w != p->lw || p->h != p->lh))
                set_pair(un.size, t->w * ((double)p->lw / p->w), t->h * ((double)p->lh / p->h));
            else
                set_pair(un.size, t->w, t->h);
        }
        if (centres) {
            for (int c = 0; c + 1 < nunits; c++)
                glBindSampler((GLuint)(c + 1), children[c].w == t->w && children[c].h == t->h ? centres : sampler);
            if (un.last && last) glBindSampler((GLuint)last_unit, last->w == t->w && last->h == t->h ? centres : sampler);
            if (un.first && pass >= 1 && first)
                glBindSampler((GLuint)first_unit, first->w == t->w && first->h == t->h ? centres : sampler);
        }
        target_bind(t);
        static const float clear[4] = {0, 0, 0, 0};
        /* a template of ours (no fragment= or vertex= of the node's)
         * that never discards writes every pixel of the target with
         * blending off: the clear before it would be overwritten (on
         * llvmpipe it cost 1-2 ms of a 540x540 !bloom's 11: bench/
         * PROFILE.md, issue 58, "texels at their centres") */
        if (!own_template || pg->discards) target_clear(t, clear);
        graph_draw_quad(g);
        target_finish(t);
        if (pass == 0 && find_uniform(prog, "first")) first = t;
        if (last && last != first) target_release(g->pool, last);
        last = t;
    }
    if (first && first != last) target_release(g->pool, first);
    glDisable(GL_BLEND);
    for (int k = 0; k <= first_unit; k++) bind_unit(k, 0, 0);
    glActiveTexture(GL_TEXTURE0);
    glDeleteSamplers(1, &sampler);
    if (centres) glDeleteSamplers(1, &centres);
    glUseProgram(0);
    if (failed) {
        target_release(g->pool, last);
        last = NULL;
    }
    p->target = last;
}

bool program_copy(Graph *g, GLuint tex, GlTarget *t)
{
    /* the plain compositing program of one texture: rendered without a node */
    static const char *const vsrc =
        HEADER "in vec2 position;\nout vec2 coord;\nvoid main() {\n    coord = 0.5 * position + 0.5;\n"
               "    gl_Position = vec4(position, 0.0, 1.0);\n}\n";
    static const char *const fsrc = HEADER "in vec2 coord;\nout vec4 color;\nuniform sampler2D texture0;\n"
                                           "void main() {\n    color = texture(texture0, coord);\n}\n";
    Program *prog = program_for(g->programs, vsrc, fsrc, g->frame);
    if (!prog->prog) return false;
    glUseProgram(prog->prog);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex);
    /* texel for texel: nearest (the same values as bilinear filtering at
     * the texels' centres, in less time on a CPU rasteriser:
     * bench/PROFILE.md, "lib/render/gl/pass_program.c: nearest sampling
     * for a copy") */
    glBindSampler(0, g->nearest);
    GLint loc = glGetUniformLocation(prog->prog, "texture0");
    glUniform1i(loc, 0);
    /* into a cleared target: no blending (the same values: over nothing
     * is the picture itself), which on a CPU rasteriser also spares
     * reading, decoding and encoding the target again */
    glDisable(GL_BLEND);
    target_bind(t);
    graph_draw_quad(g);
    target_finish(t);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
    return true;
}

double program_seed_hash(const Vec *v)
{
    int64_t h = (int64_t)vec_hash(v, false);
    if (h == -1) h = -2;   /* Python's hash() never gives -1 */
    return (double)h / 281474976710656.0;   /* / 2^48, as Python divides an int by an int */
}

/* }===== */
