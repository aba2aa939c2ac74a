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

/* GL and EGL names: epoxy's pointer epoxy_NAME for each. */
#define FL_GL_POINTERS(X) \
    X(eglBindAPI) X(eglCreateContext) X(eglDestroyContext) X(eglGetError) X(eglGetPlatformDisplayEXT) \
    X(eglInitialize) X(eglMakeCurrent) X(eglQueryString) X(eglReleaseThread) X(eglTerminate) X(glActiveTexture) \
    X(glAttachShader) X(glBindBuffer) X(glBindBufferBase) X(glBindFramebuffer) X(glBindRenderbuffer) \
    X(glBindTexture) X(glBindVertexArray) X(glBlendEquation) X(glBlendFunc) X(glBlitFramebuffer) \
    X(glBufferData) X(glBufferSubData) X(glCheckFramebufferStatus) X(glClear) X(glClearColor) X(glClearDepth) \
    X(glCompileShader) X(glCreateProgram) X(glCreateShader) X(glCullFace) X(glDeleteBuffers) X(glDeleteFramebuffers) \
    X(glDeleteProgram) X(glDeleteRenderbuffers) X(glDeleteShader) X(glDeleteTextures) X(glDeleteVertexArrays) \
    X(glDepthMask) X(glDisable) X(glDrawBuffer) X(glDrawElementsInstanced) X(glEnable) X(glEnableVertexAttribArray) \
    X(glFramebufferRenderbuffer) X(glFramebufferTexture2D) X(glGenBuffers) X(glGenFramebuffers) X(glGenRenderbuffers) \
    X(glGenTextures) X(glGenVertexArrays) X(glGetIntegerv) X(glGetMultisamplefv) X(glGetProgramInfoLog) \
    X(glGetProgramiv) X(glGetRenderbufferParameteriv) X(glGetShaderInfoLog) X(glGetShaderiv) X(glGetString) X(glGetUniformBlockIndex) \
    X(glGetUniformLocation) X(glLinkProgram) X(glPixelStorei) X(glReadBuffer) X(glReadPixels) X(glRenderbufferStorage) \
    X(glRenderbufferStorageMultisample) X(glShaderSource) X(glTexImage2D) X(glTexImage2DMultisample) X(glTexParameteri) X(glUniform1f) \
    X(glUniform1i) X(glUniform1iv) X(glUniform2f) X(glUniform2fv) X(glUniform3f) X(glUniformBlockBinding) X(glUniformMatrix4fv) \
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
extern const void *fl_gl;
#define FL_GL ((const GlLib *)fl_gl)

/* Load libepoxy if it is not loaded yet (thread-safe; only the first call
 * does any work) and say whether its entry points can be called.
 *   errors: false with one line in [why] ([cap] bytes): the library or
 *           one of its symbols missing; the same answer every time. */
bool gl_lib_ready(char *why, size_t cap);

/* The names the render files call. */
#define epoxy_gl_version (FL_GL->f_epoxy_gl_version)
#define epoxy_has_gl_extension (FL_GL->f_epoxy_has_gl_extension)
#undef eglBindAPI
#define eglBindAPI (*FL_GL->p_eglBindAPI)
#undef eglCreateContext
#define eglCreateContext (*FL_GL->p_eglCreateContext)
#undef eglDestroyContext
#define eglDestroyContext (*FL_GL->p_eglDestroyContext)
#undef eglGetError
#define eglGetError (*FL_GL->p_eglGetError)
#undef eglGetPlatformDisplayEXT
#define eglGetPlatformDisplayEXT (*FL_GL->p_eglGetPlatformDisplayEXT)
#undef eglInitialize
#define eglInitialize (*FL_GL->p_eglInitialize)
#undef eglMakeCurrent
#define eglMakeCurrent (*FL_GL->p_eglMakeCurrent)
#undef eglQueryString
#define eglQueryString (*FL_GL->p_eglQueryString)
#undef eglReleaseThread
#define eglReleaseThread (*FL_GL->p_eglReleaseThread)
#undef eglTerminate
#define eglTerminate (*FL_GL->p_eglTerminate)
#undef glActiveTexture
#define glActiveTexture (*FL_GL->p_glActiveTexture)
#undef glAttachShader
#define glAttachShader (*FL_GL->p_glAttachShader)
#undef glBindBuffer
#define glBindBuffer (*FL_GL->p_glBindBuffer)
#undef glBindBufferBase
#define glBindBufferBase (*FL_GL->p_glBindBufferBase)
#undef glBindFramebuffer
#define glBindFramebuffer (*FL_GL->p_glBindFramebuffer)
#undef glBindRenderbuffer
#define glBindRenderbuffer (*FL_GL->p_glBindRenderbuffer)
#undef glBindTexture
#define glBindTexture (*FL_GL->p_glBindTexture)
#undef glBindVertexArray
#define glBindVertexArray (*FL_GL->p_glBindVertexArray)
#undef glBlendEquation
#define glBlendEquation (*FL_GL->p_glBlendEquation)
#undef glBlendFunc
#define glBlendFunc (*FL_GL->p_glBlendFunc)
#undef glBlitFramebuffer
#define glBlitFramebuffer (*FL_GL->p_glBlitFramebuffer)
#undef glBufferData
#define glBufferData (*FL_GL->p_glBufferData)
#undef glBufferSubData
#define glBufferSubData (*FL_GL->p_glBufferSubData)
#undef glCheckFramebufferStatus
#define glCheckFramebufferStatus (*FL_GL->p_glCheckFramebufferStatus)
#undef glDrawBuffer
#define glDrawBuffer (*FL_GL->p_glDrawBuffer)
#undef glReadBuffer
#define glReadBuffer (*FL_GL->p_glReadBuffer)
#undef glTexImage2DMultisample
#define glTexImage2DMultisample (*FL_GL->p_glTexImage2DMultisample)
#undef glClear
#define glClear (*FL_GL->p_glClear)
#undef glClearColor
#define glClearColor (*FL_GL->p_glClearColor)
#undef glClearDepth
#define glClearDepth (*FL_GL->p_glClearDepth)
#undef glCompileShader
#define glCompileShader (*FL_GL->p_glCompileShader)
#undef glCreateProgram
#define glCreateProgram (*FL_GL->p_glCreateProgram)
#undef glCreateShader
#define glCreateShader (*FL_GL->p_glCreateShader)
#undef glCullFace
#define glCullFace (*FL_GL->p_glCullFace)
#undef glDeleteBuffers
#define glDeleteBuffers (*FL_GL->p_glDeleteBuffers)
#undef glDeleteFramebuffers
#define glDeleteFramebuffers (*FL_GL->p_glDeleteFramebuffers)
#undef glDeleteProgram
#define glDeleteProgram (*FL_GL->p_glDeleteProgram)
#undef glDeleteRenderbuffers
#define glDeleteRenderbuffers (*FL_GL->p_glDeleteRenderbuffers)
#undef glDeleteShader
#define glDeleteShader (*FL_GL->p_glDeleteShader)
#undef glDeleteTextures
#define glDeleteTextures (*FL_GL->p_glDeleteTextures)
#undef glDeleteVertexArrays
#define glDeleteVertexArrays (*FL_GL->p_glDeleteVertexArrays)
#undef glDepthMask
#define glDepthMask (*FL_GL->p_glDepthMask)
#undef glDisable
#define glDisable (*FL_GL->p_glDisable)
#undef glDrawElementsInstanced
#define glDrawElementsInstanced (*FL_GL->p_glDrawElementsInstanced)
#undef glEnable
#define glEnable (*FL_GL->p_glEnable)
#undef glEnableVertexAttribArray
#define glEnableVertexAttribArray (*FL_GL->p_glEnableVertexAttribArray)
#undef glFramebufferRenderbuffer
#define glFramebufferRenderbuffer (*FL_GL->p_glFramebufferRenderbuffer)
#undef glFramebufferTexture2D
#define glFramebufferTexture2D (*FL_GL->p_glFramebufferTexture2D)
#undef glGenBuffers
#define glGenBuffers (*FL_GL->p_glGenBuffers)
#undef glGenFramebuffers
#define glGenFramebuffers (*FL_GL->p_glGenFramebuffers)
#undef glGenRenderbuffers
#define glGenRenderbuffers (*FL_GL->p_glGenRenderbuffers)
#undef glGenTextures
#define glGenTextures (*FL_GL->p_glGenTextures)
#undef glGenVertexArrays
#define glGenVertexArrays (*FL_GL->p_glGenVertexArrays)
#undef glGetIntegerv
#define glGetIntegerv (*FL_GL->p_glGetIntegerv)
#undef glGetMultisamplefv
#define glGetMultisamplefv (*FL_GL->p_glGetMultisamplefv)
#undef glGetProgramInfoLog
#define glGetProgramInfoLog (*FL_GL->p_glGetProgramInfoLog)
#undef glGetProgramiv
#define glGetProgramiv (*FL_GL->p_glGetProgramiv)
#undef glGetRenderbufferParameteriv
#define glGetRenderbufferParameteriv (*FL_GL->p_glGetRenderbufferParameteriv)
#undef glGetShaderInfoLog
#define glGetShaderInfoLog (*FL_GL->p_glGetShaderInfoLog)
#undef glGetShaderiv
#define glGetShaderiv (*FL_GL->p_glGetShaderiv)
#undef glGetString
#define glGetString (*FL_GL->p_glGetString)
#undef glGetUniformBlockIndex
#define glGetUniformBlockIndex (*FL_GL->p_glGetUniformBlockIndex)
#undef glGetUniformLocation
#define glGetUniformLocation (*FL_GL->p_glGetUniformLocation)
#undef glLinkProgram
#define glLinkProgram (*FL_GL->p_glLinkProgram)
#undef glPixelStorei
#define glPixelStorei (*FL_GL->p_glPixelStorei)
#undef glReadPixels
#define glReadPixels (*FL_GL->p_glReadPixels)
#undef glRenderbufferStorage
#define glRenderbufferStorage (*FL_GL->p_glRenderbufferStorage)
#undef glRenderbufferStorageMultisample
#define glRenderbufferStorageMultisample (*FL_GL->p_glRenderbufferStorageMultisample)
#undef glShaderSource
#define glShaderSource (*FL_GL->p_glShaderSource)
#undef glTexImage2D
#define glTexImage2D (*FL_GL->p_glTexImage2D)
#undef glTexParameteri
#define glTexParameteri (*FL_GL->p_glTexParameteri)
#undef glUniform1f
#define glUniform1f (*FL_GL->p_glUniform1f)
#undef glUniform1i
#define glUniform1i (*FL_GL->p_glUniform1i)
#undef glUniform1iv
#define glUniform1iv (*FL_GL->p_glUniform1iv)
#undef glUniform2f
#define glUniform2f (*FL_GL->p_glUniform2f)
#undef glUniform2fv
#define glUniform2fv (*FL_GL->p_glUniform2fv)
#undef glUniform3f
#define glUniform3f (*FL_GL->p_glUniform3f)
#undef glUniformBlockBinding
#define glUniformBlockBinding (*FL_GL->p_glUniformBlockBinding)
#undef glUniformMatrix4fv
#define glUniformMatrix4fv (*FL_GL->p_glUniformMatrix4fv)
#undef glUseProgram
#define glUseProgram (*FL_GL->p_glUseProgram)
#undef glVertexAttribDivisor
#define glVertexAttribDivisor (*FL_GL->p_glVertexAttribDivisor)
#undef glVertexAttribPointer
#define glVertexAttribPointer (*FL_GL->p_glVertexAttribPointer)
#undef glViewport
#define glViewport (*FL_GL->p_glViewport)

#endif
