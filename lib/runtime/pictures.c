/* pictures.c: the render graph and the physics view a runtime keeps from
 * frame to frame (see pictures.h). The graph is made by the first frame
 * that draws (or the first call that needs it), with the settings a front
 * end gave before then (shown windows, --record, the live scale).
 */
#include "pictures.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "rnode.h"

struct Pictures {
    GraphEnv env;    /* what the graph is made with */
    Graph *graph;    /* the windows' passes, made by the first frame that draws */
    View *view;      /* draws the physics view (its 3D renderer kept across frames) */
    bool show;       /* windows are shown: each is composited every frame */
    char *record;    /* --record FILE, until the graph is made */
    double scale;    /* pictures_set_scale's, until the graph is made */
    int max_samples;
    bool calls_back;  /* a frame's windows held a function: drawn on the
                         runtime's thread alone from then on (api_drawing.c) */
    char folder[4096];
};

Pictures *pictures_new(const GraphEnv *env)
{
    Pictures *p = mem_calloc(1, sizeof *p);
    p->env = *env;
    /* skipped kinds are worth a warning here: a shown window lacks them */
    p->env.log.debug = true;
    p->view = view_new_fit(env->symbols);
    p->scale = 1;
    return p;
}

Graph *pictures_graph(Pictures *p)
{
    if (!p->graph) {
        p->graph = graph_new(&p->env);
        graph_show_windows(p->graph, p->show);
        graph_record_first(p->graph, p->record);
        graph_set_scale(p->graph, p->scale, p->max_samples);
    }
    return p->graph;
}

Graph *pictures_graph_made(const Pictures *p) { return p->graph; }

void pictures_free(Pictures *p)
{
    if (!p) return;
    graph_free(p->graph);
    view_close(p->view);
    free(p->record);
    free(p);
}

int pictures_render(Pictures *p, const Node *root, const GraphFrame *f, bool windows)
{
    if (!root) return 0;
    GraphFrame frame = *f;
    p->folder[0] = '\0';
    if (frame.script) {
        const char *script = frame.script, *slash = strrchr(script, '/');
        if (slash && (size_t)(slash - script) < sizeof p->folder)
            snprintf(p->folder, sizeof p->folder, "%.*s", (int)(slash - script), script);
        if (slash == script) snprintf(p->folder, sizeof p->folder, "/");
    }
    frame.folder = p->folder;
    return graph_frame(pictures_graph(p), root, &frame, windows);
}

void pictures_record_first(Pictures *p, const char *path)
{
    free(p->record);
    p->record = path && *path ? mem_strdup(path) : NULL;
    if (p->graph) graph_record_first(p->graph, p->record);
}

int pictures_finish_records(Pictures *p)
{
    return p->graph ? graph_finish_records(p->graph) : 0;
}

bool pictures_shown(const Pictures *p) { return p->show; }

bool pictures_draws_for_files(const Pictures *p, const Node *root)
{
    return graph_draws_for_files(root, p->record != NULL, p->show);
}

bool pictures_calls_back(Pictures *p, const Node *root)
{
    if (p->calls_back || !root) return p->calls_back;
    for (size_t i = 0; i < rnode_nchildren(root) && !p->calls_back; i++) {
        const Node *w = rnode_child(root, i);
        if (graph_is_window(w) && node_has_function(w)) p->calls_back = true;
    }
    return p->calls_back;
}

void pictures_show_windows(Pictures *p)
{
    if (p->show) return;
    p->show = true;
    if (p->graph) graph_show_windows(p->graph, true);
}

void pictures_set_scale(Pictures *p, double scale, int max_samples)
{
    p->scale = scale;   /* (graph_set_scale takes what is out of range as none) */
    p->max_samples = max_samples;
    if (p->graph) graph_set_scale(p->graph, p->scale, p->max_samples);
}

View *pictures_view(Pictures *p, const RenderLog **log)
{
    if (log) *log = &p->env.log;
    return p->view;
}
