/* api_drawing.c: the public functions of flitter.h's "Pictures drawn
 * beside the frame loop": a frame's picture held for a drawing thread
 * (its tree and engine names, nothing copied), drawn there by the
 * runtime's render graph, and given back on the frame loop's thread.
 *
 * Why this is safe while the frame loop's thread steps the next frame:
 * - the held tree is never changed: the evaluator changes a node or a
 *   vector in place only while it holds the one reference to it, and the
 *   picture holds one more to the root (so to everything below it);
 * - the drawing thread changes no reference count of the tree's values
 *   (the render graph keeps copies of what it keeps, vec_copy_deep), and
 *   looks engine names up in the picture's own array, not the runtime's;
 * - the two threads share the memory budget (atomic counts, mem.h) and
 *   the symbol table (its lock), and nothing else: the drawing thread
 *   allocates outside the runtime's pool (which is the frame loop's) and
 *   reports nothing through fl_error();
 * - a tree whose windows hold a function (an SDF's `function=`, called
 *   back while it is drawn) is not handed over (pictures_calls_back).
 */
#include <stdlib.h>
#include <string.h>

#include "flitter.h"
#include "graph.h"
#include "mem.h"
#include "pictures.h"
#include "runtime.h"

struct fl_picture {
    Node *root;          /* the frame's tree, held */
    GraphFrame frame;    /* its engine values; name: picture_name */
    uint32_t nnames;     /* the engine names and defines, held */
    Str **names;
    Vec **values;
    char *script;        /* the frame's script path (a copy), or NULL */
    bool drawn;          /* fl_picture_draw has drawn it */
};

/* GraphFrame.name over the picture's own names: a shader's uniforms of
 * engine names (Flitter docs/shaders.md) read the frame's values. */
static const Vec *picture_name(void *ctx, const char *name, size_t len)
{
    const fl_picture *pic = ctx;
    for (uint32_t i = 0; i < pic->nnames; i++)
        if (pic->names[i]->len == len && memcmp(pic->names[i]->bytes, name, len) == 0) return pic->values[i];
    return NULL;
}

fl_picture *fl_picture_take(fl_runtime *rt)
{
    if (!rt || fl_frame_count(rt) == 0) return NULL;
    Pictures *p = rt_pictures(rt);
    const Node *root = rt_root(rt);
    if (!root || !pictures_shown(p) || pictures_calls_back(p, root)) return NULL;
    fl_picture *pic = calloc(1, sizeof *pic);
    const char *script = rt_script_path(rt);
    char *copy = script ? strdup(script) : NULL;
    if (!pic || (script && !copy)) {
        free(pic);
        free(copy);
        return NULL;
    }
    pic->root = rt_hold_root(rt);
    pic->nnames = rt_hold_globals(rt, &pic->names, &pic->values);
    rt_graph_frame(rt, &pic->frame);
    pic->script = copy;
    pic->frame.script = copy;
    pic->frame.name = picture_name;
    pic->frame.ctx = pic;
    return pic;
}

int fl_picture_draw(fl_runtime *rt, fl_picture *pic)
{
    if (!rt || !pic) return -1;
    if (pic->drawn) return 0;
    /* the runtime's budget and failure handler, on this thread too
     * (mem.h); no pool: the runtime's is the frame loop's */
    MemHandler prev = rt_enter(rt);
    int rc = pictures_render(rt_pictures(rt), pic->root, &pic->frame, true);
    mem_leave(prev);
    pic->drawn = true;
    return rc;
}

unsigned fl_picture_texture(fl_runtime *rt, fl_picture *pic, size_t index, int *width, int *height)
{
    int w = 0, h = 0;
    unsigned tex = 0;
    if (rt && pic) {
        fl_picture_draw(rt, pic);
        Graph *g = pictures_graph_made(rt_pictures(rt));
        if (g) tex = graph_window_texture(g, index, &w, &h);
    }
    if (width) *width = w;
    if (height) *height = h;
    return tex;
}

int fl_picture_read(fl_runtime *rt, fl_picture *pic, size_t index, uint32_t *pixels, int width, int height,
                    size_t stride)
{
    if (!rt || !pic || !pixels || width < 1 || height < 1 || width > 16384 || height > 16384 ||
        stride < (size_t)width * 4 || stride % 4 != 0 || stride > (size_t)INT32_MAX)
        return -1;
    const Node *win = NULL;
    size_t k = 0;
    for (uint32_t i = 0; i < pic->root->nchildren && !win; i++) {
        const Node *c = pic->root->children[i];
        if (graph_is_window(c) && k++ == index) win = c;
    }
    int w, h;
    if (!win || (graph_window_size(win, &w, &h), w != width || h != height)) return -1;
    fl_picture_draw(rt, pic);
    Graph *g = pictures_graph_made(rt_pictures(rt));
    MemHandler prev = rt_enter(rt);
    int rc = g ? graph_read_window(g, index, pixels, width, height, stride) : -1;
    mem_leave(prev);
    if (rc != 0)   /* nothing drawn: transparent, as fl_draw_window gives it */
        for (int y = 0; y < height; y++) memset((char *)pixels + (size_t)y * stride, 0, (size_t)width * 4);
    return 0;
}

long fl_picture_frame(const fl_picture *pic) { return pic ? pic->frame.frame : -1; }

void fl_picture_free(fl_runtime *rt, fl_picture *pic)
{
    if (!pic) return;
    if (rt) rt_release_held(rt, pic->root, pic->nnames, pic->names, pic->values);
    free(pic->script);
    free(pic);
}
