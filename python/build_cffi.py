"""Emit the C source of flitter_c._flitter_cffi (cffi API mode) to argv[1].

The declarations below are the subset of include/flitter.h the Python module
uses; the C compiler checks them against the real header, so a mismatch
fails the build rather than a call.
"""
import sys

import cffi

CDEF = r"""
typedef struct fl_runtime fl_runtime;
typedef void (*fl_log_fn)(void *ctx, int kind, const char *line);
typedef void (*fl_error_fn)(void *ctx, const char *message);
typedef void (*fl_write_fn)(void *ctx, const char *text, size_t len);
typedef struct fl_options {
    double fps; long frames; bool realtime; long max_physics_steps;
    volatile int *interrupt; int threads; int pairs; int particles; int physics;
    bool no_simplify; fl_log_fn log; fl_error_fn error; void *ctx;
    ...;
} fl_options;
typedef int (*fl_state_fn)(void *ctx, const char *key_text, const char *value_text);
typedef int (*fl_particle_fn)(void *ctx, const char *id_text, const double *position,
                              const double *velocity, size_t dims);
typedef struct fl_window_info { int width, height; bool offscreen; ...; } fl_window_info;

const char *fl_version(void);
fl_options fl_default_options(void);
bool fl_parse_physics(const char *text, int *out);
fl_runtime *fl_new(const fl_options *opts);
void fl_free(fl_runtime *rt);
const char *fl_error(const fl_runtime *rt);
int fl_define(fl_runtime *rt, const char *name, const char *value_text);
int fl_define_numbers(fl_runtime *rt, const char *name, const double *values, size_t n);
int fl_load(fl_runtime *rt, const char *path);
int fl_load_text(fl_runtime *rt, const char *name, const char *text, size_t len);
int fl_step(fl_runtime *rt);
long fl_frame_count(const fl_runtime *rt);
double fl_frame_time(const fl_runtime *rt);
double fl_next_frame_time(const fl_runtime *rt);
long fl_state_get(fl_runtime *rt, const char *key_text, char *buf, size_t cap);
int fl_state_set(fl_runtime *rt, const char *key_text, const char *value_text);
int fl_state_set_numbers(fl_runtime *rt, const char *key_text, const double *values, size_t n);
size_t fl_state_count(const fl_runtime *rt);
size_t fl_state_iterate(fl_runtime *rt, fl_state_fn fn, void *ctx);
int fl_save_state(fl_runtime *rt, const char *path);
int fl_restore_state(fl_runtime *rt, const char *path);
void fl_dump_state(fl_runtime *rt, fl_write_fn fn, void *ctx);
int fl_dump_tree(fl_runtime *rt, fl_write_fn fn, void *ctx);
size_t fl_number_text(double x, char *buf, size_t cap);
int fl_view(fl_runtime *rt, const char *path, size_t *nsystems);
size_t fl_windows(fl_runtime *rt, fl_window_info *out, size_t cap);
int fl_draw_window(fl_runtime *rt, size_t index, uint32_t *pixels, int width, int height, size_t stride);
int fl_draw_view(fl_runtime *rt, uint32_t *pixels, int width, int height, size_t stride, size_t *nsystems);
long fl_particles(fl_runtime *rt, const char *system_text, fl_particle_fn fn, void *ctx);

extern "Python" void _py_log(void *ctx, int kind, const char *line);
extern "Python" void _py_write(void *ctx, const char *text, size_t len);
extern "Python" int _py_state(void *ctx, const char *key_text, const char *value_text);
extern "Python" int _py_particle(void *ctx, const char *id_text, const double *position,
                                 const double *velocity, size_t dims);
"""

ffi = cffi.FFI()
ffi.cdef(CDEF)
ffi.set_source("flitter_c._flitter_cffi", '#include "flitter.h"\n')

if __name__ == "__main__":
    ffi.emit_c_code(sys.argv[1])
