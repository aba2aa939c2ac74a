/* canvas3d_program.c: compiling and linking the standard lighting
 * programs of `!canvas3d` (see canvas3d_program.h). */
#include "canvas3d_program.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "canvas3d_shaders.h"
#include "mem.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

static GLuint compile(GLenum type, const char *src, Buf *err)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char logtext[512] = "";
        glGetShaderInfoLog(s, sizeof logtext, NULL, logtext);
        buf_printf(err, "canvas3d: shader does not compile: %s\n", logtext);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

/* Link [sh] from [vsrc] and the fragment shader of [key] as [variant]. */
static bool link(C3dShader *sh, const char *vsrc, const C3dFragSpec *key, int variant, Buf *err)
{
    memset(sh, 0, sizeof *sh);
    C3dFragSpec spec = *key;
    spec.variant = variant;
    size_t need = canvas3d_fragment_source(NULL, 0, &spec) + 1;
    char *fs = mem_alloc(need);
    canvas3d_fragment_source(fs, need, &spec);
    GLuint v = compile(GL_VERTEX_SHADER, vsrc, err);
    GLuint f = v ? compile(GL_FRAGMENT_SHADER, fs, err) : 0;
    free(fs);
    if (!f) {
        if (v) glDeleteShader(v);
        return false;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char logtext[512] = "";
        glGetProgramInfoLog(p, sizeof logtext, NULL, logtext);
        buf_printf(err, "canvas3d: shader program does not link: %s\n", logtext);
        glDeleteProgram(p);
        return false;
    }
    sh->prog = p;
    GLuint lights = glGetUniformBlockIndex(p, "Lights");
    if (lights != GL_INVALID_INDEX) glUniformBlockBinding(p, lights, 1);
#define U(name) sh->u_##name = glGetUniformLocation(p, #name)
    U(view_position); U(view_focus); U(orthographic); U(fog_min); U(fog_max); U(fog_curve);
    U(fog_color); U(monochrome); U(tint); U(light_ends); U(inverse_pv); U(viewport_size); U(nsamples);
    U(sample_offsets); U(billboard); U(proxy);
#undef U
    sh->u_pv = glGetUniformLocation(p, "pv_matrix");
    GLint backfaces = glGetUniformLocation(p, "backface_data");
    if (backfaces >= 0) {
        glUseProgram(p);
        glUniform1i(backfaces, 0);
    }
    static const char *const tex_names[C3D_TEXTURES] = {"albedo_texture", "metal_texture", "roughness_texture",
                                                       "ao_texture", "emissive_texture", "transparency_texture"};
    for (int k = 0; k < C3D_TEXTURES; k++) {
        GLint t = glGetUniformLocation(p, tex_names[k]);
        if (t >= 0) {
            glUseProgram(p);
            glUniform1i(t, C3D_TEXTURE_UNIT + k);
        }
    }
    GLint occluders = glGetUniformLocation(p, "occluders");
    if (occluders >= 0) {
        glUseProgram(p);
        glUniform1i(occluders, 1);
    }
    if (sh->u_billboard >= 0) {
        /* the vertex shader's proxy: the octagon for the BILLBOARD
         * variant, the box for the other impostors */
        glUseProgram(p);
        glUniform1i(sh->u_billboard, variant == C3D_FRAG_BILLBOARD || variant == C3D_FRAG_BILLBOARD_OCCLUDED ||
                                         variant == C3D_FRAG_PROXY);
    }
    if (sh->u_proxy >= 0) {
        glUseProgram(p);
        glUniform1i(sh->u_proxy, variant == C3D_FRAG_PROXY);
    }
    return true;
}

bool c3d_program_make(C3dProgram *p, const C3dFragSpec *key, Buf *err, Buf *note)
{
    memset(p, 0, sizeof *p);
    p->key = *key;
    p->key.variant = 0;
    if (!link(&p->mesh, canvas3d_vertex_source, &p->key, C3D_FRAG_MESH, err)) return false;
    /* a textured program draws meshes only (impostors have no texture coordinates) */
    if (!key->textures && epoxy_has_gl_extension("GL_ARB_sample_shading")) {
        Buf ignored = BUF_INIT;
        /* without the extension (or with a driver that cannot) the
         * impostor program may fail: spheres are meshes then, quietly;
         * the billboard program failing where it did not is a fault of
         * ours, worth a word */
        if (link(&p->impostor, canvas3d_impostor_vertex_source, &p->key, C3D_FRAG_IMPOSTOR, &ignored)) {
            buf_reset(&ignored);
            if (!link(&p->billboard, canvas3d_impostor_vertex_source, &p->key, C3D_FRAG_BILLBOARD, &ignored))
                buf_printf(note, "canvas3d: spheres on octagons are drawn on their boxes instead: %s\n",
                           buf_line(&ignored));
        }
        buf_free(&ignored);
    }
    glGenBuffers(1, &p->ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, p->ubo);
    glBufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)p->key.max_lights * 64, NULL, GL_DYNAMIC_DRAW);
    return true;
}

/* Link the pair of programs [a] (fragment [va]) and [b] (fragment [vb]),
 * both with vertex shader [vsrc], of [p]'s key, when [b] is not made yet
 * and *[failed] is not set; on failure, [a] is deleted again and
 * *[failed] set, so that the pair is not tried again. */
static bool link_pair(C3dProgram *p, C3dShader *a, int va, C3dShader *b, int vb, const char *vsrc, bool *failed,
                      Buf *err)
{
    if (b->prog) return true;
    if (*failed) return false;
    if (link(a, vsrc, &p->key, va, err) && link(b, vsrc, &p->key, vb, err)) return true;
    if (a->prog) glDeleteProgram(a->prog);
    memset(a, 0, sizeof *a);
    *failed = true;
    return false;
}

bool c3d_program_translucency(C3dProgram *p, Buf *err)
{
    return link_pair(p, &p->backface, C3D_FRAG_BACKFACE, &p->translucent, C3D_FRAG_TRANSLUCENT,
                     canvas3d_vertex_source, &p->translucency_failed, err);
}

bool c3d_program_occlusion(C3dProgram *p)
{
    Buf err = BUF_INIT;   /* the caller draws without occlusion, quietly */
    bool ok = link_pair(p, &p->depth, C3D_FRAG_DEPTH, &p->occluded, C3D_FRAG_OCCLUDED, canvas3d_vertex_source,
                        &p->occlusion_failed, &err);
    buf_free(&err);
    return ok;
}

bool c3d_program_proxies(C3dProgram *p)
{
    if (!p->billboard.prog) return false;
    Buf err = BUF_INIT;   /* the caller draws without proxies, quietly */
    bool ok = link_pair(p, &p->proxy, C3D_FRAG_PROXY, &p->billboard_occluded, C3D_FRAG_BILLBOARD_OCCLUDED,
                        canvas3d_impostor_vertex_source, &p->proxies_failed, &err);
    buf_free(&err);
    return ok;
}

void c3d_program_free(C3dProgram *p)
{
    if (p->proxy.prog) glDeleteProgram(p->proxy.prog);
    if (p->billboard_occluded.prog) glDeleteProgram(p->billboard_occluded.prog);
    if (p->depth.prog) glDeleteProgram(p->depth.prog);
    if (p->occluded.prog) glDeleteProgram(p->occluded.prog);
    if (p->mesh.prog) glDeleteProgram(p->mesh.prog);
    if (p->impostor.prog) glDeleteProgram(p->impostor.prog);
    if (p->billboard.prog) glDeleteProgram(p->billboard.prog);
    if (p->backface.prog) glDeleteProgram(p->backface.prog);
    if (p->translucent.prog) glDeleteProgram(p->translucent.prog);
    if (p->ubo) glDeleteBuffers(1, &p->ubo);
    memset(p, 0, sizeof *p);
}
