/* gl_lib.h: libepoxy (OpenGL's and EGL's entry points), loaded with dlopen
 * the first time a 3D canvas is drawn, not linked.
 *
 * Why: linking libepoxy maps and relocates its thousands of entry points
 * in every process, whether it draws in 3D or not (most runs do not draw
 * at all; bench/PROFILE.md, "lib/render/gl/gl_lib.h: libepoxy opened on
 * first use"). The headers (libepoxy-dev) are still needed to build; at
 * run time libepoxy.so.0 is opened by soname, and it opens EGL and the GL
 * driver itself, as it always does.
 *
 * libepoxy's GL and EGL names are macros for its own function pointers
 * (glClear is epoxy_glClear, a pointer that epoxy rewrites when it first
 * resolves the function). This header, included after <epoxy/gl.h> and
 * <epoxy/egl.h> and after every header that includes them, makes each
 * name used in lib/ a call through the address of epoxy's pointer
 * (FL_GL_POINTERS), and epoxy's own functions calls through the table
 * (FL_GL_FUNCTIONS); a name missing from the lists fails to link. The
 * table is process-wide, like the dynamic linker's own: filled once
 * (dynload.h, under a mutex), never changed, shared by every runtime in the
 * process. gl_context_new calls gl_lib_ready before any other GL or EGL
 * call, and every other GL call is made with a GlContext. */
#ifndef FL_RENDER_GL_LIB_H
#define FL_RENDER_GL_LIB_H

#include <stdbool.h>
#include <stddef.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "buf.h"

/* GL and EGL names: epoxy's pointer epoxy_NAME for each (gl_names.h, made
 * from this list at build time, turns each NAME into a call through it). */
#define FL_GL_POINTERS(X) \
    X(eglBindAPI) X(eglCreateContext) X(eglDestroyContext) X(eglGetError) X(eglGetPlatformDisplayEXT) \
    X(eglInitialize) X(eglMakeCurrent) X(eglQueryString) X(eglReleaseThread) X(eglTerminate) \
    X(glActiveTexture) X(glAttachShader) X(glBindBuffer) X(glBindAttribLocation) X(glBindBufferBase) X(glBindFramebuffer) \
    X(glBindRenderbuffer) X(glBindSampler) X(glBindTexture) X(glBindVertexArray) X(glBlendEquation) \
    X(glBlendFunc) X(glBlendFuncSeparate) X(glBlitFramebuffer) X(glBufferData) X(glBufferSubData) \
    X(glCheckFramebufferStatus) X(glClear) X(glClearColor) X(glClearDepth) X(glClientWaitSync) \
    X(glColorMask) X(glCompileShader) X(glCreateProgram) X(glCreateShader) X(glCullFace) X(glDeleteBuffers) \
    X(glDeleteFramebuffers) X(glDeleteProgram) X(glDeleteRenderbuffers) X(glDeleteSamplers) \
    X(glDeleteShader) X(glDeleteSync) X(glDeleteTextures) X(glDeleteVertexArrays) X(glDepthMask) \
    X(glDisable) X(glDrawArrays) X(glDrawBuffer) X(glDrawElementsInstanced) X(glEnable) \
    X(glEnableVertexAttribArray) X(glFenceSync) X(glFinish) X(glFlush) X(glFramebufferRenderbuffer) \
    X(glFramebufferTexture2D) X(glGenBuffers) X(glGenFramebuffers) X(glGenRenderbuffers) X(glGenSamplers) \
    X(glGenTextures) X(glGenVertexArrays) X(glGetActiveUniform) X(glGetAttribLocation) X(glGetError) \
    X(glGetIntegerv) X(glGetMultisamplefv) X(glGetProgramInfoLog) X(glGetProgramiv) \
    X(glGetRenderbufferParameteriv) X(glGetShaderInfoLog) X(glGetShaderiv) X(glGetString) \
    X(glGetUniformBlockIndex) X(glGetUniformLocation) X(glLinkProgram) X(glPixelStorei) X(glReadBuffer) \
    X(glReadPixels) X(glRenderbufferStorage) X(glRenderbufferStorageMultisample) X(glSamplerParameterfv) \
    X(glSamplerParameteri) X(glScissor) X(glShaderSource) X(glTexImage2D) X(glTexImage2DMultisample) \
    X(glTexParameterfv) X(glTexParameteri) X(glTexSubImage2D) X(glUniform1f) X(glUniform1fv) X(glUniform1i) X(glUniform1iv) \
    X(glUniform1uiv) X(glUniform2f) X(glUniform2fv) X(glUniform2iv) X(glUniform2uiv) X(glUniform3f) \
    X(glUniform3fv) X(glUniform3iv) X(glUniform3uiv) X(glUniform4fv) X(glUniform4iv) X(glUniform4uiv) \
    X(glUniform1dv) X(glUniform2dv) X(glUniform3dv) X(glUniform4dv) X(glUniformBlockBinding) \
    X(glUniformMatrix2fv) X(glUniformMatrix3fv) X(glUniformMatrix4fv) X(glUniformMatrix2x3fv) \
    X(glUniformMatrix2x4fv) X(glUniformMatrix3x2fv) X(glUniformMatrix3x4fv) X(glUniformMatrix4x2fv) \
    X(glUniformMatrix4x3fv) X(glUniformMatrix2dv) X(glUniformMatrix3dv) X(glUniformMatrix4dv) \
    X(glUseProgram) X(glVertexAttribDivisor) X(glVertexAttribPointer) X(glViewport) X(glWaitSync)

/* epoxy's own functions. */
#define FL_GL_FUNCTIONS(X) X(epoxy_gl_version) X(epoxy_has_gl_extension)

typedef struct GlLib {
#define FL_GL_POINTER_FIELD(name) __typeof__(&epoxy_##name) p_##name;
    FL_GL_POINTERS(FL_GL_POINTER_FIELD)
#undef FL_GL_POINTER_FIELD
#define FL_GL_FUNCTION_FIELD(name) __typeof__(&name) f_##name;
    FL_GL_FUNCTIONS(FL_GL_FUNCTION_FIELD)
#undef FL_GL_FUNCTION_FIELD
} GlLib;

/* The filled table (NULL before gl_lib_ready succeeds). */
extern const void *fl_gl;
#define FL_GL ((const GlLib *)fl_gl)

/* Load libepoxy if it is not loaded yet (thread-safe; only the first call
 * does any work) and say whether its entry points can be called.
 *   errors: false with one line appended to [why] (may be NULL): the library or
 *           one of its symbols missing; the same answer every time. */
bool gl_lib_ready(Buf *why);

/* The names the render files call: epoxy's own functions through the
 * table, and every GL and EGL name of FL_GL_POINTERS through epoxy's
 * pointer (the generated gl_names.h). */
#define epoxy_gl_version (FL_GL->f_epoxy_gl_version)
#define epoxy_has_gl_extension (FL_GL->f_epoxy_has_gl_extension)
#include "gl_names.h"

#endif
