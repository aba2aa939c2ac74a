/* avlib.h: FFmpeg's functions, loaded at run time (dlopen) the first time
 * a video is recorded or a picture or video is read, not linked.
 *
 * Why: linking libavcodec loads its whole dependency tree into every
 * program that links libflitter, whether it records videos or not; on
 * Debian 12 that includes libjxl's libhwy, whose load-time initialiser
 * executes RDTSCP, an instruction valgrind 3.19 cannot run, so every
 * program (and the whole test suite under valgrind) would die with
 * SIGILL before main. Loaded on demand, only a run that writes or reads a
 * video or reads a picture pays for FFmpeg. The headers (the -dev
 * packages) are still needed to build; at run time the libraries of the
 * same major versions are opened by soname (libavcodec.so.59 for the
 * FFmpeg 5.1 headers, ...), so the structure layouts match.
 *
 * Each AvLib holds its own function pointers (no process-wide table); the
 * libraries stay loaded once opened (dlopen handles are counted, a second
 * load is a lookup), as unloading FFmpeg while its encoder threads or
 * atexit handlers may remain is not safe.
 */
#ifndef FL_RENDER_AVLIB_H
#define FL_RENDER_AVLIB_H

#include <stddef.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/log.h>
#include <libavutil/mathematics.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>

#include "buf.h"

/* Every FFmpeg function video.c (encoding) and media_*.c (decoding)
 * call, with the library it comes from (X(library, name)); the one list
 * that makes both AvLib's fields and avlib_load's table of names. */
#define AVLIB_FUNCTIONS(X)                                                                            \
    X(avutil, av_log_get_level) X(avutil, av_log_set_level) X(avutil, av_strerror)                    \
    X(avutil, av_get_pix_fmt) X(avutil, av_get_pix_fmt_name) X(avutil, av_pix_fmt_desc_get)           \
    X(avutil, av_dict_set) X(avutil, av_dict_get) X(avutil, av_dict_free)                             \
    X(avutil, av_frame_alloc) X(avutil, av_frame_free) X(avutil, av_frame_get_buffer)                 \
    X(avutil, av_frame_make_writable)                                                                 \
    X(swscale, sws_getContext) X(swscale, sws_freeContext) X(swscale, sws_scale)                      \
    X(swscale, sws_setColorspaceDetails) X(swscale, sws_getCoefficients)                              \
    X(avcodec, avcodec_find_encoder_by_name) X(avcodec, avcodec_find_encoder)                         \
    X(avcodec, avcodec_descriptor_get_by_name) X(avcodec, avcodec_find_best_pix_fmt_of_list)          \
    X(avcodec, avcodec_alloc_context3) X(avcodec, avcodec_free_context) X(avcodec, avcodec_open2)     \
    X(avcodec, avcodec_parameters_from_context) X(avcodec, avcodec_send_frame)                        \
    X(avcodec, avcodec_receive_packet) X(avcodec, av_packet_alloc) X(avcodec, av_packet_free)         \
    X(avcodec, av_packet_rescale_ts)                                                                  \
    X(avformat, avformat_alloc_output_context2) X(avformat, avformat_free_context)                    \
    X(avformat, avformat_query_codec) X(avformat, avformat_new_stream) X(avformat, avio_open)         \
    X(avformat, avio_closep) X(avformat, avformat_write_header) X(avformat, av_interleaved_write_frame) \
    X(avformat, av_write_trailer)                                                                     \
    X(avutil, av_frame_unref) X(avutil, av_rescale_q)                                                 \
    X(avcodec, avcodec_find_decoder) X(avcodec, avcodec_parameters_to_context)                        \
    X(avcodec, avcodec_send_packet) X(avcodec, avcodec_receive_frame) X(avcodec, avcodec_flush_buffers) \
    X(avcodec, av_packet_unref)                                                                       \
    X(avformat, avformat_alloc_context) X(avformat, avformat_open_input)                              \
    X(avformat, avformat_find_stream_info) X(avformat, av_find_best_stream) X(avformat, av_read_frame) \
    X(avformat, av_seek_frame) X(avformat, avformat_close_input)

typedef struct AvLib {
#define AVLIB_FIELD(lib, name) __typeof__(&name) name;
    AVLIB_FUNCTIONS(AVLIB_FIELD)
#undef AVLIB_FIELD
} AvLib;

/* Open FFmpeg's four libraries and fill a new AvLib (free() it).
 *   errors: NULL with "cannot load FFmpeg: REASON" appended to [err] when
 *           a library or a function is missing. */
AvLib *avlib_load(Buf *err);

#endif
