/* geom_model_file.c: model files read through Assimp's C interface,
 * opened with dlopen (see geom_model_file.h). */
#include "geom_model_file.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "dynload.h"
#include "mem.h"

/* The soname of the major version the headers describe. */
#define ASSIMP_SONAME "libassimp.so.5"

typedef struct AssimpLib {
    const struct aiScene *(*import_file)(const char *file, unsigned int flags);
    void (*release_import)(const struct aiScene *scene);
    const char *(*error_string)(void);
} AssimpLib;

static const DynEntry entries[] = {
    {"aiImportFile", offsetof(AssimpLib, import_file)},
    {"aiReleaseImport", offsetof(AssimpLib, release_import)},
    {"aiGetErrorString", offsetof(AssimpLib, error_string)},
};

/* Process-wide, filled once; Assimp's C interface keeps its last error in
 * one string of its own, so imports are taken one at a time. */
static AssimpLib table;
static const void *published;
static pthread_mutex_t import_lock = PTHREAD_MUTEX_INITIALIZER;

/* Assimp's entry points; NULL with the reason appended to [why] when it
 * cannot be loaded. */
static const AssimpLib *assimp(Buf *why)
{
    static DynLib lib = DYNLIB_INIT;
    if (!dynload_ready(&lib, ASSIMP_SONAME, "Assimp", entries, sizeof entries / sizeof *entries, &table,
                       &published, why))
        return NULL;
    return published;
}

/* Append the triangles of [scene] to [out]; false with a reason past
 * [max_vertices]. */
static bool gather(const struct aiScene *scene, size_t max_vertices, GeomMesh *out, Buf *err)
{
    size_t nv = 0, nt = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        nv += m->mNumVertices;
        nt += m->mNumFaces;
    }
    if (nv == 0 || nt == 0) {
        buf_printf(err, "cannot load model: no triangles in it\n");
        return false;
    }
    if (nv > max_vertices || nv > UINT32_MAX / 4 || nt > UINT32_MAX / 4) {
        buf_printf(err, "cannot load model: %zu vertices, more than the %zu the memory budget allows\n", nv,
                   max_vertices);
        return false;
    }
    out->pos = mem_alloc(nv * 3 * sizeof(double));
    out->normal = mem_alloc(nv * 3 * sizeof(float));
    out->uv = mem_alloc(nv * 2 * sizeof(float));
    out->tri = mem_alloc(nt * 3 * sizeof(uint32_t));
    uint32_t base = 0, t = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        if (!(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        for (unsigned v = 0; v < m->mNumVertices; v++) {
            size_t k = base + v;
            out->pos[k * 3] = m->mVertices[v].x;
            out->pos[k * 3 + 1] = m->mVertices[v].y;
            out->pos[k * 3 + 2] = m->mVertices[v].z;
            float nx = 0, ny = 0, nz = 0;
            if (m->mNormals) nx = m->mNormals[v].x, ny = m->mNormals[v].y, nz = m->mNormals[v].z;
            out->normal[k * 3] = nx, out->normal[k * 3 + 1] = ny, out->normal[k * 3 + 2] = nz;
            float u = 0, w = 0;
            if (m->mTextureCoords[0]) u = m->mTextureCoords[0][v].x, w = m->mTextureCoords[0][v].y;
            out->uv[k * 2] = u, out->uv[k * 2 + 1] = w;
        }
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            const struct aiFace *face = &m->mFaces[f];
            if (face->mNumIndices != 3) continue;
            bool ok = true;
            for (int c = 0; c < 3; c++) ok = ok && face->mIndices[c] < m->mNumVertices;
            if (!ok) continue;
            for (int c = 0; c < 3; c++) out->tri[(size_t)t * 3 + c] = base + face->mIndices[c];
            t++;
        }
        base += m->mNumVertices;
    }
    out->npos = base;
    out->ntri = t;
    if (t == 0) {
        buf_printf(err, "cannot load model: no triangles in it\n");
        return false;
    }
    return true;
}

int geom_model_file_read(const char *path, size_t max_vertices, GeomMesh *out, Buf *err)
{
    memset(out, 0, sizeof *out);
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
        buf_printf(err, "cannot load model: %s\n", stat(path, &st) != 0 ? "no such file" : "not a regular file");
        return -1;
    }
    Buf why = BUF_INIT;
    const AssimpLib *ai = assimp(&why);
    if (!ai) {
        buf_printf(err, "cannot load model: %s\n", buf_line(&why));
        buf_free(&why);
        return -1;
    }
    buf_free(&why);
    unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                     aiProcess_PreTransformVertices | aiProcess_SortByPType;
    pthread_mutex_lock(&import_lock);
    const struct aiScene *scene = ai->import_file(path, flags);
    if (!scene) {
        const char *e = ai->error_string();
        buf_printf(err, "cannot load model: %s\n", e && e[0] ? e : "not a model file");
        pthread_mutex_unlock(&import_lock);
        return -1;
    }
    pthread_mutex_unlock(&import_lock);
    bool ok = gather(scene, max_vertices, out, err);
    ai->release_import(scene);
    if (!ok) {
        geom_mesh_free(out);
        return -1;
    }
    return 0;
}
