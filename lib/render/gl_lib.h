/* gl_lib.h: libepoxy (OpenGL's and EGL's entry points), loaded with dlopen
 * the first time a 3D canvas is drawn, not linked.
 *
 * Why: linking libepoxy maps and relocates its thousands of entry points
 * in every process, about 0.65 ms, whether it draws in 3D or not (most
 * runs do not draw at all). The headers (libepoxy-dev) are still needed
 * to build; at run time libepoxy.so.0 is opened by soname, and it opens
 * EGL and the GL driver itself, as it always does.
 *
 * libepoxy's GL and EGL names are macros for its own function pointers
 * (glClear is epoxy_glClear, a pointer that epoxy rewrites when it first
 * resolves the function). This header, included after <epoxy/gl.h> and
 * <epoxy/egl.h> and after every header that includes them, makes each
 * name used in lib/ a call through the address of epoxy's pointer
 * (FL_GL_POINTERS), and epoxy's own functions calls through the table
 * (FL_GL_FUNCTIONS); a name missing from the lists fails to link. The
 * table is process-wide, like the dynamic linker's own: filled once,
 * under pthread_once, never changed, shared by every runtime in the
 * process. gl_context_new calls gl_lib_ready before any other GL or EGL
 * call, and every other GL call is made with a GlContext. */
#ifndef FL_RENDER_GL_LIB_H
#define FL_RENDER_GL_LIB_H

#include <stdbool.h>
#include <stddef.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

/* GL and EGL names: epoxy's pointer epoxy_NAME for each. */
#define FL_GL_POINTERS(X) \
    X(eglBindAPI) X(eglCreateContext) X(eglDestroyContext) X(eglGetError) X(eglGetPlatformDisplayEXT) \
    X(eglInitialize) X(eglMakeCurrent) X(eglQueryString) X(eglReleaseThread) X(eglTerminate) X(glActiveTexture) \
    X(glAttachShader) X(glBindBuffer) X(glBindBufferBase) X(glBindFramebuffer) X(glBindRenderbuffer) \
    X(glBindTexture) X(glBindVertexArray) X(glBlendEquation) X(glBlendFunc) X(glBlitFramebuffer) \
    X(glBufferData) X(glBufferSubData) X(glCheckFramebufferStatus) X(glClear) X(glClearColor) X(glClearDepth) \
    X(glCompileShader) X(glCreateProgram) X(glCreateShader) X(glCullFace) X(glDeleteBuffers) X(glDeleteFramebuffers) \
    X(glDeleteProgram) X(glDeleteRenderbuffers) X(glDeleteShader) X(glDeleteTextures) X(glDeleteVertexArrays) \
    X(glDepthMask) X(glDisable) X(glDrawElementsInstanced) X(glEnable) X(glEnableVertexAttribArray) \
    X(glFramebufferRenderbuffer) X(glFramebufferTexture2D) X(glGenBuffers) X(glGenFramebuffers) X(glGenRenderbuffers) \
    X(glGenTextures) X(glGenVertexArrays) X(glGetIntegerv) X(glGetMultisamplefv) X(glGetProgramInfoLog) \
    X(glGetProgramiv) X(glGetShaderInfoLog) X(glGetShaderiv) X(glGetString) X(glGetUniformBlockIndex) \
    X(glGetUniformLocation) X(glLinkProgram) X(glPixelStorei) X(glReadPixels) X(glRenderbufferStorage) \
    X(glRenderbufferStorageMultisample) X(glShaderSource) X(glTexImage2D) X(glTexParameteri) X(glUniform1f) \
    X(glUniform1i) X(glUniform2f) X(glUniform2fv) X(glUniform3f) X(glUniformBlockBinding) X(glUniformMatrix4fv) \
    X(glUseProgram) X(glVertexAttribDivisor) X(glVertexAttribPointer) X(glViewport)

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
extern const GlLib *fl_gl;

/* Load libepoxy if it is not loaded yet (thread-safe; only the first call
 * does any work) and say whether its entry points can be called.
 *   errors: false with one line in [why] ([cap] bytes): the library or
 *           one of its symbols missing; the same answer every time. */
bool gl_lib_ready(char *why, size_t cap);

/* The names the render files call. */
#define epoxy_gl_version (fl_gl->f_epoxy_gl_version)
#define epoxy_has_gl_extension (fl_gl->f_epoxy_has_gl_extension)
#undef eglBindAPI
#define eglBindAPI (*fl_gl->p_eglBindAPI)
#undef eglCreateContext
#define eglCreateContext (*fl_gl->p_eglCreateContext)
#undef eglDestroyContext
#define eglDestroyContext (*fl_gl->p_eglDestroyContext)
#undef eglGetError
#define eglGetError (*fl_gl->p_eglGetError)
#undef eglGetPlatformDisplayEXT
#define eglGetPlatformDisplayEXT (*fl_gl->p_eglGetPlatformDisplayEXT)
#undef eglInitialize
#define eglInitialize (*fl_gl->p_eglInitialize)
#undef eglMakeCurrent
#define eglMakeCurrent (*fl_gl->p_eglMakeCurrent)
#undef eglQueryString
#define eglQueryString (*fl_gl->p_eglQueryString)
#undef eglReleaseThread
#define eglReleaseThread (*fl_gl->p_eglReleaseThread)
#undef eglTerminate
#define eglTerminate (*fl_gl->p_eglTerminate)
#undef glActiveTexture
#define glActiveTexture (*fl_gl->p_glActiveTexture)
#undef glAttachShader
#define glAttachShader (*fl_gl->p_glAttachShader)
#undef glBindBuffer
#define glBindBuffer (*fl_gl->p_glBindBuffer)
#undef glBindBufferBase
#define glBindBufferBase (*fl_gl->p_glBindBufferBase)
#undef glBindFramebuffer
#define glBindFramebuffer (*fl_gl->p_glBindFramebuffer)
#undef glBindRenderbuffer
#define glBindRenderbuffer (*fl_gl->p_glBindRenderbuffer)
#undef glBindTexture
#define glBindTexture (*fl_gl->p_glBindTexture)
#undef glBindVertexArray
#define glBindVertexArray (*fl_gl->p_glBindVertexArray)
#undef glBlendEquation
#define glBlendEquation (*fl_gl->p_glBlendEquation)
#undef glBlendFunc
#define glBlendFunc (*fl_gl->p_glBlendFunc)
#undef glBlitFramebuffer
#define glBlitFramebuffer (*fl_gl->p_glBlitFramebuffer)
#undef glBufferData
#define glBufferData (*fl_gl->p_glBufferData)
#undef glBufferSubData
#define glBufferSubData (*fl_gl->p_glBufferSubData)
#undef glCheckFramebufferStatus
#define glCheckFramebufferStatus (*fl_gl->p_glCheckFramebufferStatus)
#undef glClear
#define glClear (*fl_gl->p_glClear)
#undef glClearColor
#define glClearColor (*fl_gl->p_glClearColor)
#undef glClearDepth
#define glClearDepth (*fl_gl->p_glClearDepth)
#undef glCompileShader
#define glCompileShader (*fl_gl->p_glCompileShader)
#undef glCreateProgram
#define glCreateProgram (*fl_gl->p_glCreateProgram)
#undef glCreateShader
#define glCreateShader (*fl_gl->p_glCreateShader)
#undef glCullFace
#define glCullFace (*fl_gl->p_glCullFace)
#undef glDeleteBuffers
#define glDeleteBuffers (*fl_gl->p_glDeleteBuffers)
#undef glDeleteFramebuffers
#define glDeleteFramebuffers (*fl_gl->p_glDeleteFramebuffers)
#undef glDeleteProgram
#define glDeleteProgram (*fl_gl->p_glDeleteProgram)
#undef glDeleteRenderbuffers
#define glDeleteRenderbuffers (*fl_gl->p_glDeleteRenderbuffers)
#undef glDeleteShader
#define glDeleteShader (*fl_gl->p_glDeleteShader)
#undef glDeleteTextures
#define glDeleteTextures (*fl_gl->p_glDeleteTextures)
#undef glDeleteVertexArrays
#define glDeleteVertexArrays (*fl_gl->p_glDeleteVertexArrays)
#undef glDepthMask
#define glDepthMask (*fl_gl->p_glDepthMask)
#undef glDisable
#define glDisable (*fl_gl->p_glDisable)
#undef glDrawElementsInstanced
#define glDrawElementsInstanced (*fl_gl->p_glDrawElementsInstanced)
#undef glEnable
#define glEnable (*fl_gl->p_glEnable)
#undef glEnableVertexAttribArray
#define glEnableVertexAttribArray (*fl_gl->p_glEnableVertexAttribArray)
#undef glFramebufferRenderbuffer
#define glFramebufferRenderbuffer (*fl_gl->p_glFramebufferRenderbuffer)
#undef glFramebufferTexture2D
#define glFramebufferTexture2D (*fl_gl->p_glFramebufferTexture2D)
#undef glGenBuffers
#define glGenBuffers (*fl_gl->p_glGenBuffers)
#undef glGenFramebuffers
#define glGenFramebuffers (*fl_gl->p_glGenFramebuffers)
#undef glGenRenderbuffers
#define glGenRenderbuffers (*fl_gl->p_glGenRenderbuffers)
#undef glGenTextures
#define glGenTextures (*fl_gl->p_glGenTextures)
#undef glGenVertexArrays
#define glGenVertexArrays (*fl_gl->p_glGenVertexArrays)
#undef glGetIntegerv
#define glGetIntegerv (*fl_gl->p_glGetIntegerv)
#undef glGetMultisamplefv
#define glGetMultisamplefv (*fl_gl->p_glGetMultisamplefv)
#undef glGetProgramInfoLog
#define glGetProgramInfoLog (*fl_gl->p_glGetProgramInfoLog)
#undef glGetProgramiv
#define glGetProgramiv (*fl_gl->p_glGetProgramiv)
#undef glGetShaderInfoLog
#define glGetShaderInfoLog (*fl_gl->p_glGetShaderInfoLog)
#undef glGetShaderiv
#define glGetShaderiv (*fl_gl->p_glGetShaderiv)
#undef glGetString
#define glGetString (*fl_gl->p_glGetString)
#undef glGetUniformBlockIndex
#define glGetUniformBlockIndex (*fl_gl->p_glGetUniformBlockIndex)
#undef glGetUniformLocation
#define glGetUniformLocation (*fl_gl->p_glGetUniformLocation)
#undef glLinkProgram
#define glLinkProgram (*fl_gl->p_glLinkProgram)
#undef glPixelStorei
#define glPixelStorei (*fl_gl->p_glPixelStorei)
#undef glReadPixels
#define glReadPixels (*fl_gl->p_glReadPixels)
#undef glRenderbufferStorage
#define glRenderbufferStorage (*fl_gl->p_glRenderbufferStorage)
#undef glRenderbufferStorageMultisample
#define glRenderbufferStorageMultisample (*fl_gl->p_glRenderbufferStorageMultisample)
#undef glShaderSource
#define glShaderSource (*fl_gl->p_glShaderSource)
#undef glTexImage2D
#define glTexImage2D (*fl_gl->p_glTexImage2D)
#undef glTexParameteri
#define glTexParameteri (*fl_gl->p_glTexParameteri)
#undef glUniform1f
#define glUniform1f (*fl_gl->p_glUniform1f)
#undef glUniform1i
#define glUniform1i (*fl_gl->p_glUniform1i)
#undef glUniform2f
#define glUniform2f (*fl_gl->p_glUniform2f)
#undef glUniform2fv
#define glUniform2fv (*fl_gl->p_glUniform2fv)
#undef glUniform3f
#define glUniform3f (*fl_gl->p_glUniform3f)
#undef glUniformBlockBinding
#define glUniformBlockBinding (*fl_gl->p_glUniformBlockBinding)
#undef glUniformMatrix4fv
#define glUniformMatrix4fv (*fl_gl->p_glUniformMatrix4fv)
#undef glUseProgram
#define glUseProgram (*fl_gl->p_glUseProgram)
#undef glVertexAttribDivisor
#define glVertexAttribDivisor (*fl_gl->p_glVertexAttribDivisor)
#undef glVertexAttribPointer
#define glVertexAttribPointer (*fl_gl->p_glVertexAttribPointer)
#undef glViewport
#define glViewport (*fl_gl->p_glViewport)

#endif
