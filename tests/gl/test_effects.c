/* test_effects.c: `!shader` and the built-in filters of the render graph
 * (lib/render/gl/pass_program.c, pass_filters.c and glsl/), pixels
 * checked at known places against values computed here by hand from
 * Flitter's behaviour (docs/shaders.md; render/window/__init__.py
 * ProgramNode, shaders.py and the glsl folder): uniforms from attributes,
 * the unset ones and the 'alpha' substring rule, templates, passes and
 * `last`, samplers, compile and template errors, and each filter fed by
 * child !shader nodes of known constant linear light (16-bit float
 * targets hold the values used here exactly). A window pixel is
 * 0xAARRGGBB: RGB the 8-bit sRGB encoding of the premultiplied linear
 * light, A the linear alpha; the GL's 8-bit sRGB encoding may round a
 * value half a step either way (sRGB(0.5) is 187.5), so encoded values
 * are checked within 1. Rows are counted from the top; a shader's
 * `coord.y` is 1 - (row + 0.5) / H. Only flitter.h is used. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "flitter.h"

#define W 16
#define H 16

static char scratch[64];
static char logged[8192];   /* the log lines of the last runtime */

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_effects.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    unlink(path);
    return rmdir(scratch);
}

static void keep_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, "%s\n", line);
}

/* A new runtime at [fps] frames per second (0: the default), logging
 * into `logged` (emptied), with [script] written to scratch/main.fl and
 * loaded. */
static fl_runtime *load_script(const char *script, double fps)
{
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(script, f);
    fclose(f);
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    if (fps > 0) o.fps = fps;
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_load(rt, path), 0);
    return rt;
}

/* One frame of [rt]: step, then draw its first [n] windows (W x H each). */
static void frame(fl_runtime *rt, int n, uint32_t pix[][W * H])
{
    assert_int_equal(fl_step(rt), 0);
    for (int k = 0; k < n; k++) assert_int_equal(fl_draw_window(rt, (size_t)k, pix[k], W, H, W * 4), 0);
    assert_null(strstr(logged, "no OpenGL"));
}

/* One frame of [script] with [n] windows drawn into [pix]; nothing
 * logged. */
static void draw(const char *script, int n, uint32_t pix[][W * H])
{
    fl_runtime *rt = load_script(script, 0);
    frame(rt, n, pix);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    fl_free(rt);
}

static uint32_t at(const uint32_t *pix, int x, int y) { return pix[y * W + x]; }
static int chan(uint32_t p, int shift) { return (int)((p >> shift) & 0xff); }

/* The window's 8-bit sRGB encoding of linear light [x] (clamped). */
static int srgb(double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return (int)lround(s * 255);
}

static int alpha8(double a) { return (int)lround((a < 0 ? 0 : a > 1 ? 1 : a) * 255); }

/* Pixel (x, y) of [pix] is premultiplied linear light r, g, b at alpha
 * a, each channel within [tol] of the 8-bit value. */
static void expect(const uint32_t *pix, int x, int y, double r, double g, double b, double a, int tol)
{
    uint32_t p = at(pix, x, y);
    int want[4] = {alpha8(a), srgb(r), srgb(g), srgb(b)};
    for (int k = 0; k < 4; k++) {
        int got = chan(p, 24 - 8 * k);
        if (abs(got - want[k]) > tol)
            fail_msg("pixel (%d,%d) is %08x: channel %c is %d, expected %d (+-%d)", x, y, p, "ARGB"[k], got,
                     want[k], tol);
    }
}

static void expect_exact(const uint32_t *pix, int x, int y, uint32_t want)
{
    if (at(pix, x, y) != want) fail_msg("pixel (%d,%d) is %08x, expected %08x", x, y, at(pix, x, y), want);
}

static int count(const char *hay, const char *needle)
{
    int n = 0;
    for (const char *s = strstr(hay, needle); s; s = strstr(s + 1, needle)) n++;
    return n;
}

/* {===== fragments shared by the tests (Flitter ''' strings) */

/* The constant premultiplied colour `rgba`. */
#define SOLID \
    "let solid = '''${HEADER}\n" \
    "out vec4 color;\n" \
    "uniform vec4 rgba;\n" \
    "void main() {\n" \
    "    color = rgba;\n" \
    "}\n" \
    "'''\n"

/* Opaque red on the left half, opaque green on the right. */
#define HALVES \
    "let halves = '''${HEADER}\n" \
    "in vec2 coord;\n" \
    "out vec4 color;\n" \
    "void main() {\n" \
    "    color = coord.x < 0.5 ? vec4(1.0, 0.0, 0.0, 1.0) : vec4(0.0, 1.0, 0.0, 1.0);\n" \
    "}\n" \
    "'''\n"

/* One white pixel at column 8, row 7 (GL pixel 8;8), the rest transparent. */
#define DOT \
    "let dot = '''${HEADER}\n" \
    "in vec2 coord;\n" \
    "out vec4 color;\n" \
    "uniform vec2 size;\n" \
    "void main() {\n" \
    "    vec2 p = floor(coord * size);\n" \
    "    color = p == vec2(8.0, 8.0) ? vec4(1.0) : vec4(0.0);\n" \
    "}\n" \
    "'''\n"

/* Red coord.x, green coord.y: a ramp that linear filtering reproduces. */
#define RAMP \
    "let ramp = '''${HEADER}\n" \
    "in vec2 coord;\n" \
    "out vec4 color;\n" \
    "void main() {\n" \
    "    color = vec4(coord, 0.0, 1.0);\n" \
    "}\n" \
    "'''\n"

/* }===== */

/* {===== !shader: uniforms */

/* Uniforms from attributes (docs/shaders.md "Standard uniforms";
 * ProgramNode.render): red=0.25 and gb=0.5;0.125 as given; `count`, an
 * int, floors 2.7 to 2 (Vector.match(n, int)); `wrong`, a vec2 given 3
 * numbers, does not match and, like the unset `nothing`, reads 0; the
 * unset `ph` and `a` are substrings of 'alpha' (Flitter's `name in
 * 'alpha'`) and read 1, as does `alpha` itself. Left half (red, gb):
 * sRGB 137, 188, 99; top right (nothing + wrong, ph, a): 0, 255, 255;
 * bottom right (0.25 alpha, 0.125 count): 137, 137. */
static void shader_uniforms(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    draw("let frag = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform float red;\n"
         "uniform vec2 gb;\n"
         "uniform int count;\n"
         "uniform vec2 wrong;\n"
         "uniform float nothing;\n"
         "uniform float ph;\n"
         "uniform float a;\n"
         "uniform float alpha;\n"
         "void main() {\n"
         "    if (coord.x < 0.5)\n"
         "        color = vec4(red, gb, 1.0);\n"
         "    else if (coord.y > 0.5)\n"
         "        color = vec4(nothing + wrong.x + wrong.y, ph, a, 1.0);\n"
         "    else\n"
         "        color = vec4(0.25 * alpha, 0.125 * float(count), 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=frag red=0.25 gb=0.5;0.125 count=2.7 wrong=1;2;3\n",
         1, pix);
    assert_int_equal(srgb(0.25), 137);
    assert_int_equal(srgb(0.5), 188);
    assert_int_equal(srgb(0.125), 99);
    expect(pix[0], 3, 3, 0.25, 0.5, 0.125, 1, 1);
    expect(pix[0], 4, 12, 0.25, 0.5, 0.125, 1, 1);
    expect_exact(pix[0], 12, 3, 0xff00ffffu);
    expect(pix[0], 12, 12, 0.25, 0.25, 0, 1, 1);
}

/* Array uniforms (set_uniform_vector): `xs[3]` takes 3 numbers, one
 * each; `pairs[2]`, a vec2 array given one vec2's worth (2 numbers, not
 * the 4 it holds), has that vector in every item; `mat` (a mat2, 4
 * numbers, column by column) given one number has it in all four.
 * Left: (xs[0], xs[1], xs[2]) = (0.125, 0.25, 0.5); right: (pairs[1],
 * mat[1][0]) = (0.25, 0.5, 0.0625). */
static void shader_arrays(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    draw("let frag = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform float xs[3];\n"
         "uniform vec2 pairs[2];\n"
         "uniform mat2 mat;\n"
         "void main() {\n"
         "    if (coord.x < 0.5)\n"
         "        color = vec4(xs[0], xs[1], xs[2], 1.0);\n"
         "    else\n"
         "        color = vec4(pairs[1], mat[1][0], 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=frag xs=0.125;0.25;0.5 pairs=0.25;0.5 mat=0.0625\n",
         1, pix);
    expect(pix[0], 3, 8, 0.125, 0.25, 0.5, 1, 1);
    expect(pix[0], 12, 8, 0.25, 0.5, 0.0625, 1, 1);
}

/* alpha=0.5 on a white shader that applies it: premultiplied 0.5 white,
 * sRGB(0.5) = 187.5 at alpha 0.5 * 255 = 127.5 (llvmpipe gives 187 and
 * 128, an NVIDIA H100's OpenGL 188 and 127: the ties of the 8-bit
 * conversions are the GL's). The default compositing program (a !shader
 * without fragment=) applies its alpha to its child the same way. */
static void shader_alpha(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw(SOLID
         "let white = '''${HEADER}\n"
         "out vec4 color;\n"
         "uniform float alpha;\n"
         "void main() {\n"
         "    color = vec4(alpha);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=white alpha=0.5\n"
         "!window size=16;16\n"
         "    !shader alpha=0.5\n"
         "        !shader fragment=solid rgba=1\n",
         2, pix);
    for (int k = 0; k < 2; k++) {
        expect(pix[k], 0, 0, 0.5, 0.5, 0.5, 0.5, 1);
        expect(pix[k], 9, 13, 0.5, 0.5, 0.5, 0.5, 1);
        assert_in_range(chan(at(pix[k], 9, 13), 24), 127, 128);
    }
}

/* The engine's names as uniforms (docs/shaders.md "Standard uniforms";
 * the engine's names reach ProgramNode.render as keyword defaults) at 2
 * frames per second, second frame (tempo 120, not real time): time 0.5,
 * beat 1, delta 1, fps 2, tempo 120, quantum 4, frame 1, performance 2.
 * Top left: (time, beat / 4, fps / 16) = (0.5, 0.25, 0.125); top right:
 * (tempo / 480, quantum / 16, delta / 2) = (0.25, 0.25, 0.5); bottom:
 * (frame / 4, performance / 4) = (0.25, 0.5). An attribute of the same
 * name comes first: time=0.125 gives red 0.125. */
static void engine_uniforms(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    fl_runtime *rt = load_script("let frag = '''${HEADER}\n"
                                 "in vec2 coord;\n"
                                 "out vec4 color;\n"
                                 "uniform float time;\n"
                                 "uniform float beat;\n"
                                 "uniform int fps;\n"
                                 "uniform float tempo;\n"
                                 "uniform float quantum;\n"
                                 "uniform float delta;\n"
                                 "uniform int frame;\n"
                                 "uniform float performance;\n"
                                 "void main() {\n"
                                 "    if (coord.y < 0.5)\n"
                                 "        color = vec4(0.25 * float(frame), 0.25 * performance, 0.0, 1.0);\n"
                                 "    else if (coord.x < 0.5)\n"
                                 "        color = vec4(time, 0.25 * beat, 0.0625 * float(fps), 1.0);\n"
                                 "    else\n"
                                 "        color = vec4(tempo / 480.0, quantum / 16.0, 0.5 * delta, 1.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=frag\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=frag time=0.125\n",
                                 2);
    frame(rt, 2, pix);
    expect(pix[0], 3, 3, 0, 0, 0.125, 1, 1);      /* frame 0: time 0, beat 0 */
    expect(pix[0], 12, 3, 0.25, 0.25, 0, 1, 1);   /* delta 0 */
    expect(pix[0], 8, 12, 0, 0.5, 0, 1, 1);
    frame(rt, 2, pix);
    expect(pix[0], 3, 3, 0.5, 0.25, 0.125, 1, 1);
    expect(pix[0], 12, 3, 0.25, 0.25, 0.5, 1, 1);
    expect(pix[0], 8, 12, 0.25, 0.5, 0, 1, 1);
    expect(pix[1], 3, 3, 0.125, 0.25, 0.125, 1, 1);
    assert_string_equal(logged, "");
    fl_free(rt);
}

/* composite= (docs/windows.md) blends each child onto the ones before:
 * (0.125, 0.25, 0, 0.25) onto (0.25, 0, 0, 0.5). Over (the default):
 * s + (1 - 0.25) d = (0.3125, 0.25, 0, 0.625); add: the sum, alpha
 * min(1, 0.75) = (0.375, 0.25, 0, 0.75); lighten: the larger of each,
 * (0.25, 0.25, 0, 0.5); blend=:multiply (composite's other name): the
 * product, (0.03125, 0, 0, 0.125). */
static void shader_composite(void **st)
{
    (void)st;
    uint32_t pix[4][W * H];
    static const char *const modes[4] = {"", " composite=:add", " composite=:lighten", " blend=:multiply"};
    char script[2048];
    int n = snprintf(script, sizeof script, "%s", SOLID);
    for (int k = 0; k < 4; k++)
        n += snprintf(script + n, sizeof script - (size_t)n,
                      "!window size=16;16\n"
                      "    !shader%s\n"
                      "        !shader fragment=solid rgba=0.25;0;0;0.5\n"
                      "        !shader fragment=solid rgba=0.125;0.25;0;0.25\n",
                      modes[k]);
    draw(script, 4, pix);
    expect(pix[0], 6, 6, 0.3125, 0.25, 0, 0.625, 1);
    expect(pix[1], 6, 6, 0.375, 0.25, 0, 0.75, 1);
    expect(pix[2], 6, 6, 0.25, 0.25, 0, 0.5, 1);
    expect(pix[3], 6, 6, 0.03125, 0, 0, 0.125, 1);
}

/* colorbits= (docs/shaders.md): 16-bit float targets by default keep
 * 1.4/255 = 0.0054902 (sRGB 17); an 8-bit target (the shader's
 * colorbits=8, or the window's, which its tree takes as default) stores
 * 1/255 (sRGB 13; 1.4 rounds and truncates alike, where GLs differ:
 * llvmpipe rounds, an NVIDIA H100 truncates). */
static void shader_colorbits(void **st)
{
    (void)st;
    uint32_t pix[3][W * H];
    draw(SOLID
         "!window size=16;16\n"
         "    !shader fragment=solid rgba=0.0054902;0.0054902;0.0054902;1\n"
         "!window size=16;16\n"
         "    !shader fragment=solid rgba=0.0054902;0.0054902;0.0054902;1 colorbits=8\n"
         "!window size=16;16 colorbits=8\n"
         "    !shader fragment=solid rgba=0.0054902;0.0054902;0.0054902;1\n",
         3, pix);
    assert_int_equal(srgb(1.4 / 255), 17);
    assert_int_equal(srgb(1 / 255.0), 13);
    expect(pix[0], 5, 5, 1.4 / 255, 1.4 / 255, 1.4 / 255, 1, 1);
    expect(pix[1], 5, 5, 1 / 255.0, 1 / 255.0, 1 / 255.0, 1, 1);
    expect(pix[2], 5, 5, 1 / 255.0, 1 / 255.0, 1 / 255.0, 1, 1);
}

/* vertex= replaces the default vertex shader (docs/shaders.md "Shader
 * programs"): one that turns `coord` upside down gives the ramp's green
 * 1 - coord.y: row 2 (coord.y 0.84375) reads 0.15625, red unchanged
 * (column 5: 0.34375). */
static void shader_vertex(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    draw(RAMP
         "let flip = '''${HEADER}\n"
         "in vec2 position;\n"
         "out vec2 coord;\n"
         "void main() {\n"
         "    coord = vec2(0.5 + 0.5 * position.x, 0.5 - 0.5 * position.y);\n"
         "    gl_Position = vec4(position, 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader vertex=flip fragment=ramp\n",
         1, pix);
    expect(pix[0], 5, 2, 0.34375, 0.15625, 0, 1, 1);
    expect(pix[0], 5, 13, 0.34375, 0.84375, 0, 1, 1);
}

/* }===== */

/* {===== templates */

/* ${k * 2} of the attribute k=0.25 is the text 0.5 (Flitter's Vector
 * arithmetic), red 0.5: sRGB 188. `% if mode == 'red'` picks its branch
 * on a string attribute: red for mode='red', blue otherwise. The
 * example of docs/shaders.md, count=3 offset=-3;4.5 as constants through
 * int() and float() of an item: (3 / 16, 3 / 16, 4.5 / 16) = (0.1875,
 * 0.1875, 0.28125); and an item prints as Python prints a float
 * (str(offset[0]) is '-3.0', str(k * 3) of k=0.1 '0.3'), else blue. */
static void template_expressions(void **st)
{
    (void)st;
    uint32_t pix[4][W * H];
    draw("let frag = '''${HEADER}\n"
         "out vec4 color;\n"
         "void main() {\n"
         "% if mode == 'red':\n"
         "    color = vec4(${k * 2}, 0.0, 0.0, 1.0);\n"
         "% else:\n"
         "    color = vec4(0.0, 0.0, ${k * 2}, 1.0);\n"
         "% endif\n"
         "}\n"
         "'''\n"
         "let consts = '''${HEADER}\n"
         "out vec4 color;\n"
         "const int count = ${int(count)};\n"
         "const vec2 offset = vec2(${float(offset[0])}, ${float(offset[1])});\n"
         "void main() {\n"
         "% if str(offset[0]) == '-3.0' and str(k * 3) == '0.3':\n"
         "    color = vec4(0.0625 * float(count), -offset.x / 16.0, offset.y / 16.0, 1.0);\n"
         "% else:\n"
         "    color = vec4(0.0, 0.0, 1.0, 1.0);\n"
         "% endif\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=frag k=0.25 mode='red'\n"
         "!window size=16;16\n"
         "    !shader fragment=frag k=0.25 mode='blue'\n"
         "!window size=16;16\n"
         "    !shader fragment=frag k=0.125 mode=\"red\"\n"
         "!window size=16;16\n"
         "    !shader fragment=consts count=3 offset=-3;4.5 k=0.1\n",
         4, pix);
    expect(pix[0], 5, 5, 0.5, 0, 0, 1, 1);
    expect(pix[1], 5, 5, 0, 0, 0.5, 1, 1);
    expect(pix[2], 5, 5, 0.25, 0, 0, 1, 1);
    expect(pix[3], 5, 5, 0.1875, 0.1875, 0.28125, 1, 1);
}

/* `% for name in child_textures` over three children (a fourth,
 * hidden=true, is not one of them): each child k adds (k + 1) times its
 * red (loop.index), 0.03125 + 2 * 0.0625 + 3 * 0.125 = 0.53125, and
 * green is len(child_textures) / 8 = 0.375. A sampler of no child
 * (texture1 of one child) reads the zero texture: only texture0's 0.25. */
static void template_child_textures(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw(SOLID
         "let frag = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "% for name in child_textures:\n"
         "uniform sampler2D ${name};\n"
         "% endfor\n"
         "void main() {\n"
         "    color = vec4(0.0, ${len(child_textures)}.0 / 8.0, 0.0, 1.0);\n"
         "% for name in child_textures:\n"
         "    color.r += ${loop.index + 1}.0 * texture(${name}, coord).r;\n"
         "% endfor\n"
         "}\n"
         "'''\n"
         "let two = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform sampler2D texture0;\n"
         "uniform sampler2D texture1;\n"
         "void main() {\n"
         "    color = texture(texture0, coord) + texture(texture1, coord);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=frag\n"
         "        !shader fragment=solid rgba=0.03125;0;0;1\n"
         "        !shader fragment=solid rgba=1;1;1;1 hidden=true\n"
         "        !shader fragment=solid rgba=0.0625;0;0;1\n"
         "        !shader fragment=solid rgba=0.125;0;0;1\n"
         "!window size=16;16\n"
         "    !shader fragment=two\n"
         "        !shader fragment=solid rgba=0.25;0;0;1\n",
         2, pix);
    expect(pix[0], 7, 7, 0.53125, 0.375, 0, 1, 1);
    expect(pix[0], 0, 15, 0.53125, 0.375, 0, 1, 1);
    expect(pix[1], 7, 7, 0.25, 0, 0, 1, 1);
}

/* }===== */

/* {===== passes and last */

/* passes=2: pass 0 writes (0.25, 0, 0.0625, 1); pass 1 reads it through
 * `last` and adds (0, 0.0625 passes, 0.125 pass, 0): (0.25, 0.125,
 * 0.1875, 1). With passes=3 pass 2 adds to pass 1's: (0.25, 0.375,
 * 0.0625 + 0.125 + 0.25 = 0.4375, 1). With downsample_passes=0 pass 0
 * draws at 8x8 (`size` 8;8, `downsample` 2): it writes (size.x / 64 =
 * 0.125, 0.125 downsample = 0.25, 0, 1), and pass 1, full size, adds
 * size.x / 64 = 0.25 to blue. Upsampled, the 8x8 picture is read with
 * the default sampler, whose border is transparent: the rows and columns
 * at the edge (half a small pixel from it) mix a quarter of it in. */
static void passes_last(void **st)
{
    (void)st;
    uint32_t pix[3][W * H];
    static const char frag[] = "let frag = '''${HEADER}\n"
                               "in vec2 coord;\n"
                               "out vec4 color;\n"
                               "uniform sampler2D last;\n"
                               "uniform int pass;\n"
                               "uniform int passes;\n"
                               "void main() {\n"
                               "    if (pass == 0)\n"
                               "        color = vec4(0.25, 0.0, 0.0625, 1.0);\n"
                               "    else\n"
                               "        color = texture(last, coord) + "
                               "vec4(0.0, 0.0625 * float(passes), 0.125 * float(pass), 0.0);\n"
                               "}\n"
                               "'''\n"
                               "let down = '''${HEADER}\n"
                               "in vec2 coord;\n"
                               "out vec4 color;\n"
                               "uniform sampler2D last;\n"
                               "uniform int pass;\n"
                               "uniform vec2 size;\n"
                               "uniform int downsample;\n"
                               "void main() {\n"
                               "    if (pass == 0)\n"
                               "        color = vec4(size.x / 64.0, 0.125 * float(downsample), 0.0, 1.0);\n"
                               "    else\n"
                               "        color = texture(last, coord) + vec4(0.0, 0.0, size.x / 64.0, 0.0);\n"
                               "}\n"
                               "'''\n";
    char script[2048];
    snprintf(script, sizeof script,
             "%s!window size=16;16\n"
             "    !shader fragment=frag passes=2\n"
             "!window size=16;16\n"
             "    !shader fragment=frag passes=3\n"
             "!window size=16;16\n"
             "    !shader fragment=down passes=2 downsample_passes=0\n",
             frag);
    draw(script, 3, pix);
    for (int y = 0; y < H; y += 5) {
        expect(pix[0], 3, y, 0.25, 0.125, 0.1875, 1, 1);
        expect(pix[1], 12, y, 0.25, 0.375, 0.4375, 1, 1);
    }
    for (int y = 1; y < H - 1; y += 4) expect(pix[2], 7, y, 0.125, 0.25, 0.25, 1, 1);
    /* row 0 (half-size row 7.75) reads 0.75 of the top texel and 0.25 of
     * the transparent border: (0.09375, 0.1875) at alpha 0.75, blue added
     * after: 0.25 */
    expect(pix[2], 7, 0, 0.09375, 0.1875, 0.25, 0.75, 1);
}

/* A `last` sampler keeps the pass's picture to the next frame: adding
 * 0.125 to last frame's red gives 0.125, 0.25, 0.375, 0.5 over four
 * frames (exact in 16-bit floats). Frame 0's `last` is the zero texture.
 * With passes=2, `last` in pass 0 is the last frame's final picture and
 * in pass 1 pass 0's: adding 0.125 then 0.0625 gives 0.1875 more a
 * frame, 0.1875 (f + 1). */
static void last_across_frames(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    fl_runtime *rt = load_script("let frag = '''${HEADER}\n"
                                 "in vec2 coord;\n"
                                 "out vec4 color;\n"
                                 "uniform sampler2D last;\n"
                                 "uniform int pass;\n"
                                 "void main() {\n"
                                 "    float add = pass == 0 ? 0.125 : 0.0625;\n"
                                 "    color = vec4(texture(last, coord).r + add, 0.0, 0.0, 1.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=frag\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=frag passes=2\n",
                                 0);
    for (int f = 0; f < 4; f++) {
        frame(rt, 2, pix);
        expect(pix[0], 0, 0, 0.125 * (f + 1), 0, 0, 1, 1);
        expect(pix[0], 15, 15, 0.125 * (f + 1), 0, 0, 1, 1);
        expect(pix[0], 6, 9, 0.125 * (f + 1), 0, 0, 1, 1);
        expect(pix[1], 0, 0, 0.1875 * (f + 1), 0, 0, 1, 1);
        expect(pix[1], 9, 6, 0.1875 * (f + 1), 0, 0, 1, 1);
    }
    assert_string_equal(logged, "");
    fl_free(rt);
}

/* }===== */

/* {===== samplers */

/* A !canvas (red left half, green right; 255s decode exactly) sampled at
 * u = 2 coord.x - 0.5: column x reads u = (x + 0.5) / 8 - 0.5. Column 0
 * (u = -0.4375) is outside: transparent by default, the border colour
 * with border=1;1;1;1, u + 1 = 0.5625 (green) with repeat=true, the edge
 * (red) with repeat=false. Column 15 (u = 1.4375): transparent, white,
 * 0.4375 (texel 7.0, between two reds), and the right edge (green).
 * Columns 5 (u = 0.1875, texel 3.0) and 8 (u = 0.5625, texel 9.0) are
 * inside: red and green, whatever the sampler. */
static void sampler_outside(void **st)
{
    (void)st;
    uint32_t pix[4][W * H];
    static const char stretch[] = "let stretch = '''${HEADER}\n"
                                  "in vec2 coord;\n"
                                  "out vec4 color;\n"
                                  "uniform sampler2D texture0;\n"
                                  "void main() {\n"
                                  "    color = texture(texture0, vec2(2.0 * coord.x - 0.5, coord.y));\n"
                                  "}\n"
                                  "'''\n";
    static const char canvas[] = "        !canvas\n"
                                 "            !rect size=8;16 fill=true color=1;0;0\n"
                                 "            !rect point=8;0 size=8;16 fill=true color=0;1;0\n";
    static const char *const attrs[4] = {"", " border=1;1;1;1", " repeat=true", " repeat=false"};
    char script[2048];
    int n = snprintf(script, sizeof script, "%s", stretch);
    for (int k = 0; k < 4; k++)
        n += snprintf(script + n, sizeof script - (size_t)n, "!window size=16;16\n    !shader fragment=stretch%s\n%s",
                      attrs[k], canvas);
    draw(script, 4, pix);
    static const uint32_t col0[4] = {0x00000000u, 0xffffffffu, 0xff00ff00u, 0xffff0000u};
    static const uint32_t col15[4] = {0x00000000u, 0xffffffffu, 0xffff0000u, 0xff00ff00u};
    for (int k = 0; k < 4; k++) {
        for (int y = 1; y < H; y += 6) {
            expect_exact(pix[k], 0, y, col0[k]);
            expect_exact(pix[k], 15, y, col15[k]);
            expect_exact(pix[k], 5, y, 0xffff0000u);
            expect_exact(pix[k], 8, y, 0xff00ff00u);
        }
    }
}

/* A child ramp whose texel x holds red x / 16, read half a texel to the
 * right (texel x + 1.0, on the edge between x and x + 1) and a quarter
 * (texel x + 0.75). Linear filtering: (2x + 1) / 32 and (x + 0.25) / 16;
 * column 4: 0.28125 and 0.265625. nearest=true: the texel the point
 * falls in, 4 / 16 = 0.25 at a quarter (and texel 4 or 5 at the edge). */
static void sampler_nearest(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw("let ramp = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform vec2 size;\n"
         "void main() {\n"
         "    color = vec4(floor(coord.x * size.x) / size.x, 0.0, 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "let shift = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform sampler2D texture0;\n"
         "void main() {\n"
         "    color = vec4(texture(texture0, coord + vec2(0.5 / 16.0, 0.0)).r,\n"
         "                 texture(texture0, coord + vec2(0.25 / 16.0, 0.0)).r, 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !shader fragment=shift\n"
         "        !shader fragment=ramp\n"
         "!window size=16;16\n"
         "    !shader fragment=shift nearest=true\n"
         "        !shader fragment=ramp\n",
         2, pix);
    for (int x = 2; x < 12; x += 3) {
        expect(pix[0], x, 6, (2 * x + 1) / 32.0, (x + 0.25) / 16, 0, 1, 1);
        int r = chan(at(pix[1], x, 6), 16);
        expect(pix[1], x, 6, abs(r - srgb(x / 16.0)) <= 1 ? x / 16.0 : (x + 1) / 16.0, x / 16.0, 0, 1, 1);
    }
    expect(pix[0], 4, 6, 0.28125, 0.265625, 0, 1, 1);
    expect(pix[1], 4, 6, abs(chan(at(pix[1], 4, 6), 16) - srgb(0.25)) <= 1 ? 0.25 : 0.3125, 0.25, 0, 1, 1);
    /* the two filters differ: linear's quarter is not the texel's value */
    assert_int_not_equal(chan(at(pix[0], 4, 6), 8), chan(at(pix[1], 4, 6), 8));
}

/* }===== */

/* {===== errors */

/* A fragment that does not compile: one "GLSL error" line over three
 * frames, no picture (the window without it is transparent; beside a
 * good child the window shows only that one), and the runtime goes on. */
static void glsl_error(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "let bad = '''${HEADER}\n"
                                 "out vec4 color;\n"
                                 "void main() {\n"
                                 "    color = vec4(undeclared_thing);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=bad\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=solid rgba=0;0.5;0;1\n"
                                 "    !shader fragment=bad\n",
                                 0);
    for (int f = 0; f < 3; f++) {
        frame(rt, 2, pix);
        expect_exact(pix[0], 3, 3, 0x00000000u);
        expect_exact(pix[0], 12, 8, 0x00000000u);
        expect(pix[1], 3, 3, 0, 0.5, 0, 1, 1);
        expect(pix[1], 12, 8, 0, 0.5, 0, 1, 1);
    }
    if (count(logged, "GLSL error") != 1) fail_msg("expected one GLSL error, log:\n%s", logged);
    assert_non_null(strstr(logged, "!shader"));
    assert_int_equal(fl_frame_count(rt), 3);
    fl_free(rt);
}

/* A shader edited into an error keeps drawing with its last program that
 * compiled (as a script that fails to reload keeps the last one running):
 * frame 0 compiles `solid` (green), frames 1 and 2 ask for `bad`: the
 * window still shows green, with one GLSL error over the two frames; a
 * shader that never compiled draws nothing (glsl_error above). */
static void glsl_error_keeps_last_good(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "let bad = '''${HEADER}\n"
                                 "out vec4 color;\n"
                                 "void main() {\n"
                                 "    color = vec4(undeclared_thing);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=(solid if frame == 0 else bad) rgba=0;0.5;0;1\n",
                                 0);
    for (int f = 0; f < 3; f++) {
        frame(rt, 1, pix);
        expect(pix[0], 3, 3, 0, 0.5, 0, 1, 1);
        expect(pix[0], 12, 8, 0, 0.5, 0, 1, 1);
    }
    if (count(logged, "GLSL error") != 1) fail_msg("expected one GLSL error, log:\n%s", logged);
    fl_free(rt);
}

/* A template naming an undefined name: one message over three frames
 * that names the template and the name, no picture, the runtime goes on. */
static void template_error(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script("let bad = '''${HEADER}\n"
                                 "out vec4 color;\n"
                                 "void main() {\n"
                                 "    color = vec4(${no_such_name});\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader fragment=bad\n",
                                 0);
    for (int f = 0; f < 3; f++) {
        frame(rt, 1, pix);
        expect_exact(pix[0], 8, 8, 0x00000000u);
    }
    if (count(logged, "no_such_name") != 1) fail_msg("expected one template error, log:\n%s", logged);
    assert_non_null(strstr(logged, "fragment template"));
    assert_null(strstr(logged, "GLSL error"));
    assert_int_equal(fl_frame_count(rt), 3);
    fl_free(rt);
}

/* }===== */

/* {===== the built-in filters */

/* !adjust of (0.25, 0.5, 0.125) (docs/shaders.md "!adjust";
 * filter_functions.glsl filter_adjust): exposure=1 doubles it, (0.5, 1,
 * 0.25); contrast=2 brightness=0.125 is 2c + 0.125 + (1 - 2) / 2 = 2c -
 * 0.375, (0.125, 0.625, -0.125 clamped to 0); tonemap=:reinhard is
 * c / (1 + c), (0.2, 1/3, 1/9). A half-transparent input (0.125, 0.25,
 * 0.0625, 0.5) is un-premultiplied first: exposure=1 gives (0.25, 0.5,
 * 0.125, 0.5). The tone map's name is taken as written (Adjust.render:
 * not lower-cased): tonemap=:Reinhard maps nothing. saturation=0 leaves
 * the value, the largest channel: grey 0.5; gamma=0.5 takes square
 * roots, (0.5, 0.70711, 0.35355); color_matrix=0;0;1;0;1;0;1;0;0 (column
 * by column: red to blue, blue to red) swaps red and blue; hue=0.5 turns
 * the hue (2 + (0.125 - 0.25) / 0.375) / 6 = 0.27778 to 0.77778 at the
 * same saturation 0.75 and value 0.5: chroma 0.375 above 0.125, sector 4
 * of 6 at 0.6667 of the way: (0.125 + 0.25, 0.125, 0.5). */
static void filter_adjust(void **st)
{
    (void)st;
    uint32_t pix[9][W * H];
    draw(SOLID
         "!window size=16;16\n"
         "    !adjust exposure=1\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust contrast=2 brightness=0.125\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust tonemap=:reinhard\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust exposure=1\n"
         "        !shader fragment=solid rgba=0.125;0.25;0.0625;0.5\n"
         "!window size=16;16\n"
         "    !adjust exposure=1 tonemap=:Reinhard\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust saturation=0\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust gamma=0.5\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust color_matrix=0;0;1;0;1;0;1;0;0\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !adjust hue=0.5\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n",
         9, pix);
    for (int y = 2; y < H; y += 6) {
        expect(pix[0], 4, y, 0.5, 1, 0.25, 1, 1);
        expect(pix[1], 4, y, 0.125, 0.625, 0, 1, 1);
        expect(pix[2], 4, y, 0.2, 1 / 3.0, 1 / 9.0, 1, 1);
        expect(pix[3], 4, y, 0.25, 0.5, 0.125, 0.5, 1);
        expect(pix[4], 4, y, 0.5, 1, 0.25, 1, 1);
        expect(pix[5], 4, y, 0.5, 0.5, 0.5, 1, 1);
        expect(pix[6], 4, y, 0.5, sqrt(0.5), sqrt(0.125), 1, 1);
        expect(pix[7], 4, y, 0.125, 0.5, 0.25, 1, 1);
        expect(pix[8], 4, y, 0.375, 0.125, 0.5, 1, 1);
    }
}

/* !blur radius=3 of one white pixel (column 8, row 7): a separable
 * normalised Gaussian of sigma 0.3 * 3 = 0.9, weights g(i) =
 * exp(-i^2 / 1.62) / S over |i| <= 3 (g = 0.44331, 0.23912, 0.03753,
 * 0.00171), so pixel (8 + dx, 7 + dy) is g(dx) g(dy) of white, alpha
 * too; nothing beyond 3 pixels. With two children a first pass
 * composites them (over: (0, 0.25, 0, 0.5) onto (0.25, 0, 0, 0.5) is
 * (0.125, 0.25, 0, 0.75)), and the default radius 0 leaves that as it
 * is. */
static void filter_blur(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw(DOT SOLID
         "!window size=16;16\n"
         "    !blur radius=3\n"
         "        !shader fragment=dot\n"
         "!window size=16;16\n"
         "    !blur\n"
         "        !shader fragment=solid rgba=0.25;0;0;0.5\n"
         "        !shader fragment=solid rgba=0;0.25;0;0.5\n",
         2, pix);
    double g[4], s = 0;
    for (int i = 0; i <= 3; i++) s += (i ? 2 : 1) * exp(-i * i / (2 * 0.9 * 0.9));
    for (int i = 0; i <= 3; i++) g[i] = exp(-i * i / (2 * 0.9 * 0.9)) / s;
    assert_true(fabs(g[0] - 0.44331) < 1e-4 && fabs(g[1] - 0.23912) < 1e-4);
    for (int dy = -3; dy <= 3; dy++)
        for (int dx = -3; dx <= 3; dx++) {
            double v = g[abs(dx)] * g[abs(dy)];
            expect(pix[0], 8 + dx, 7 + dy, v, v, v, v, 1);
        }
    expect(pix[0], 8, 7, 0.19652, 0.19652, 0.19652, 0.19652, 1);
    expect_exact(pix[0], 12, 7, 0x00000000u);
    expect_exact(pix[0], 8, 11, 0x00000000u);
    expect_exact(pix[0], 4, 3, 0x00000000u);
    for (int y = 0; y < H; y += 5)
        for (int x = 0; x < W; x += 5) expect(pix[1], x, y, 0.125, 0.25, 0, 0.75, 1);
}

/* A blur reads a texture of its own size at the centres of its texels
 * (nearest sampling there reads what bilinear does), but a child of
 * another size filtered: an 8x8 child of stripes (texel column j white
 * when j is odd) under a 16x16 !blur radius=0 is sampled at u = x/2 -
 * 0.25 texels, so column 2k is 0.75 of texel k and 0.25 of texel k - 1,
 * column 2k + 1 0.75 of texel k and 0.25 of texel k + 1: 0.25 or 0.75,
 * never 0 or 1 (which a nearest sampling of the small child would give).
 * The same stripes at 16x16 come through whole. */
static void filter_blur_other_size(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw("let stripes = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "uniform vec2 size;\n"
         "void main() {\n"
         "    color = vec4(vec3(mod(floor(coord.x * size.x), 2.0)), 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !blur radius=0\n"
         "        !shader size=8;8 fragment=stripes\n"
         "!window size=16;16\n"
         "    !blur radius=0\n"
         "        !shader fragment=stripes\n",
         2, pix);
    for (int y = 1; y < H - 1; y += 3)
        for (int k = 1; k < 7; k++) {
            double v = k % 2 ? 0.75 : 0.25;   /* texel k's share is 0.75 in both columns */
            expect(pix[0], 2 * k, y, v, v, v, 1, 1);
            expect(pix[0], 2 * k + 1, y, v, v, v, 1, 1);
            expect_exact(pix[1], 2 * k, y, 0xff000000u);
            expect_exact(pix[1], 2 * k + 1, y, 0xffffffffu);
        }
}

/* !vignette of opaque white: each axis fades linearly over `inset` of
 * the picture at both ends (coord / inset, (1 - coord) / inset). Inset
 * 0.25: column 0 (coord.x 0.03125) is 0.125, column 2 (0.15625) 0.625;
 * row 7 (coord.y 0.53125) is whole; corner (0, 0) 0.125^2 = 0.015625;
 * the middle is untouched. Inset 0.5: column 4 (0.28125) 0.5625 times
 * row 7 ((1 - 0.53125) / 0.5 = 0.9375) = 0.52734. fade=:quad eases
 * 0.125 to 2 (0.125)^2 = 0.03125 and 0.625 to 1 - 2 (0.375)^2 = 0.71875.
 * The name is taken as written (Vignette.render: `fade` not lower-cased):
 * fade=:Quad is no easing Flitter knows, so linear. */
static void filter_vignette(void **st)
{
    (void)st;
    uint32_t pix[4][W * H];
    draw(SOLID
         "!window size=16;16\n"
         "    !vignette\n"
         "        !shader fragment=solid rgba=1\n"
         "!window size=16;16\n"
         "    !vignette inset=0.5\n"
         "        !shader fragment=solid rgba=1\n"
         "!window size=16;16\n"
         "    !vignette fade=:quad\n"
         "        !shader fragment=solid rgba=1\n"
         "!window size=16;16\n"
         "    !vignette fade=:Quad\n"
         "        !shader fragment=solid rgba=1\n",
         4, pix);
    expect(pix[0], 0, 7, 0.125, 0.125, 0.125, 0.125, 1);
    expect(pix[0], 2, 7, 0.625, 0.625, 0.625, 0.625, 1);
    /* column 15: (1 - 0.96875) / 0.25; row 8 (coord.y 0.46875) whole */
    expect(pix[0], 15, 8, 0.125, 0.125, 0.125, 0.125, 1);
    expect(pix[0], 7, 0, 0.125, 0.125, 0.125, 0.125, 1);
    expect(pix[0], 0, 0, 0.015625, 0.015625, 0.015625, 0.015625, 1);
    expect_exact(pix[0], 7, 7, 0xffffffffu);
    expect_exact(pix[0], 4, 11, 0xffffffffu);
    expect(pix[1], 4, 7, 0.52734375, 0.52734375, 0.52734375, 0.52734375, 1);
    expect(pix[2], 0, 7, 0.03125, 0.03125, 0.03125, 0.03125, 1);
    expect(pix[2], 2, 7, 0.71875, 0.71875, 0.71875, 0.71875, 1);
    expect(pix[3], 0, 7, 0.125, 0.125, 0.125, 0.125, 1);
    expect(pix[3], 2, 7, 0.625, 0.625, 0.625, 0.625, 1);
}

/* !transform about the centre, y up, the last attribute first
 * (docs/shaders.md "!transform"). translate=3;2 moves the white pixel of
 * column 8, row 7 to column 11, row 5. Of the red/green halves, with
 * translate=4;0 scale=0.5;1 (scale first, then translate) a point at
 * x (from the centre) lands at x / 2 + 4: the red half covers columns
 * 8..11, green 12..15, and columns 0..7 read outside (transparent).
 * Swapped, scale=0.5;1 translate=4;0, it lands at (x + 4) / 2: red 6..9,
 * green 10..13, nothing at 0..5 and 14..15. Each column centre reads the
 * child at a texel edge between two of one colour, or beyond. rotate=0.25
 * turns a quarter about the centre (Matrix33.rotate: x towards y, y up):
 * each pixel reads the child at (y, -x) from the centre, a texel centre,
 * so the green right half is now the top half, the red the bottom.
 * keystone=1;0 (Matrix33 with kx / width in its third row) makes the
 * matrix projective: the inverse reads the child at p / (1 - p.x / 16)
 * from the centre; on a linear ramp (red coord.x, green coord.y) linear
 * filtering gives the ramp's value there exactly. */
static void filter_transform(void **st)
{
    (void)st;
    uint32_t pix[5][W * H];
    draw(DOT HALVES RAMP
         "!window size=16;16\n"
         "    !transform translate=3;2\n"
         "        !shader fragment=dot\n"
         "!window size=16;16\n"
         "    !transform translate=4;0 scale=0.5;1\n"
         "        !shader fragment=halves\n"
         "!window size=16;16\n"
         "    !transform scale=0.5;1 translate=4;0\n"
         "        !shader fragment=halves\n"
         "!window size=16;16\n"
         "    !transform rotate=0.25\n"
         "        !shader fragment=halves\n"
         "!window size=16;16\n"
         "    !transform keystone=1;0\n"
         "        !shader fragment=ramp\n",
         5, pix);
    expect_exact(pix[0], 11, 5, 0xffffffffu);
    expect_exact(pix[0], 8, 7, 0x00000000u);
    expect_exact(pix[0], 10, 5, 0x00000000u);
    expect_exact(pix[0], 11, 6, 0x00000000u);
    for (int x = 0; x < W; x++) {
        uint32_t a = x < 8 ? 0 : x < 12 ? 0xffff0000u : 0xff00ff00u;
        uint32_t b = x < 6 || x > 13 ? 0 : x < 10 ? 0xffff0000u : 0xff00ff00u;
        for (int y = 0; y < H; y += 5) {
            expect_exact(pix[1], x, y, a);
            expect_exact(pix[2], x, y, b);
            /* rotate=0.25: the right half (green) turned up */
            expect_exact(pix[3], x, y, y < 8 ? 0xff00ff00u : 0xffff0000u);
        }
    }
    /* keystone: column 12, row 7 (4.5; 0.5 from the centre) reads
     * (4.5; 0.5) / (1 - 4.5 / 16); column 3 (-4.5) divides by 1 + 4.5 / 16 */
    double k = 1 - 4.5 / 16;
    expect(pix[4], 12, 7, (8 + 4.5 / k) / 16, (8 + 0.5 / k) / 16, 0, 1, 1);
    assert_true(fabs((8 + 4.5 / k) / 16 - 0.89130) < 1e-4);
    k = 1 + 4.5 / 16;
    expect(pix[4], 3, 7, (8 - 4.5 / k) / 16, (8 + 0.5 / k) / 16, 0, 1, 1);
}

/* !feedback mixer=0.5 of opaque white at 2 frames per second: `delta`
 * is the beats since the last frame (tempo 120: 1 beat a frame after the
 * first, whose delta is 0: no last picture). The last picture's weight
 * is mixer^(delta / timebase): frame 0 has weight 1 on the zero texture,
 * transparent; frame 1 0.5 white + 0.5 of that = 0.5 (sRGB 188, alpha
 * 128); frame 2 0.5 + 0.5 * 0.5 = 0.75 (sRGB 225, alpha 191). */
static void filter_feedback(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "!window size=16;16\n"
                                 "    !feedback mixer=0.5\n"
                                 "        !shader fragment=solid rgba=1\n",
                                 2);
    frame(rt, 1, pix);
    expect_exact(pix[0], 8, 8, 0x00000000u);
    frame(rt, 1, pix);
    expect(pix[0], 8, 8, 0.5, 0.5, 0.5, 0.5, 1);
    expect(pix[0], 0, 15, 0.5, 0.5, 0.5, 0.5, 1);
    frame(rt, 1, pix);
    expect(pix[0], 8, 8, 0.75, 0.75, 0.75, 0.75, 1);
    expect(pix[0], 15, 0, 0.75, 0.75, 0.75, 0.75, 1);
    assert_int_equal(srgb(0.75), 225);
    assert_string_equal(logged, "");
    fl_free(rt);
    /* at 4 frames per second half a beat passes a frame: frame 1 keeps
     * 0.5^0.5 = 0.70711 of the last picture (nothing), 0.29289 white */
    rt = load_script(SOLID
                     "!window size=16;16\n"
                     "    !feedback mixer=0.5\n"
                     "        !shader fragment=solid rgba=1\n",
                     4);
    frame(rt, 1, pix);
    expect_exact(pix[0], 8, 8, 0x00000000u);
    frame(rt, 1, pix);
    expect(pix[0], 8, 8, 1 - sqrt(0.5), 1 - sqrt(0.5), 1 - sqrt(0.5), 1 - sqrt(0.5), 1);
    fl_free(rt);
}

/* Frames a front end does not draw (a live window dropping pictures it
 * cannot show) are not drawn at all, and the next frame drawn counts the
 * beats since the last drawn one as its delta: at 2 frames a second frame
 * 0 is drawn (transparent), frames 1 and 2 only stepped, frame 3 drawn
 * with delta 3 beats: the last picture keeps 0.5^3 = 0.125, white
 * 0.875 (sRGB 240, alpha 223); a delta of one frame's beat would give
 * 0.5. */
static void filter_feedback_skipped_frames(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "!window size=16;16\n"
                                 "    !feedback mixer=0.5\n"
                                 "        !shader fragment=solid rgba=1\n",
                                 2);
    frame(rt, 1, pix);
    expect_exact(pix[0], 8, 8, 0x00000000u);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_step(rt), 0);
    frame(rt, 1, pix);
    expect(pix[0], 8, 8, 0.875, 0.875, 0.875, 0.875, 1);
    assert_int_equal(srgb(0.875), 240);
    assert_string_equal(logged, "");
    fl_free(rt);
}


/* !feedback translate=2;1 (pixels per beat, y down as on a canvas) with
 * mixer=0.5 of the white pixel at column 8, row 7, 1 beat a frame: frame
 * 1 is half the pixel; frame 2 half the pixel again plus half of frame
 * 1 moved 2 right and 1 down: 0.5 at (8, 7), 0.25 at (10, 8), nothing
 * where frame 1's copy was not moved to. */
static void filter_feedback_moves(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script(DOT
                                 "!window size=16;16\n"
                                 "    !feedback mixer=0.5 translate=2;1\n"
                                 "        !shader fragment=dot\n",
                                 2);
    frame(rt, 1, pix);
    expect_exact(pix[0], 8, 7, 0x00000000u);
    frame(rt, 1, pix);
    expect(pix[0], 8, 7, 0.5, 0.5, 0.5, 0.5, 1);
    expect_exact(pix[0], 10, 8, 0x00000000u);
    frame(rt, 1, pix);
    expect(pix[0], 8, 7, 0.5, 0.5, 0.5, 0.5, 1);
    expect(pix[0], 10, 8, 0.25, 0.25, 0.25, 0.25, 1);
    expect_exact(pix[0], 10, 6, 0x00000000u);
    expect_exact(pix[0], 6, 8, 0x00000000u);
    expect_exact(pix[0], 9, 7, 0x00000000u);
    assert_string_equal(logged, "");
    fl_free(rt);
}

/* !chromakey of green (hue 1/3: keyed, saturation 1 > 0.75, value 1 >
 * 0.1) on the left half and red (hue 0) on the right: the mask is 0 over
 * the green, 1 over the red; blurred (radius=2: 1 half-size pixel) it is
 * still 0 at columns 0..4 and 1 at 11..15, so the green there is
 * transparent and the red untouched. hue=0 keys the red instead. */
static void filter_chromakey(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    draw("let halves = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "void main() {\n"
         "    color = coord.x < 0.5 ? vec4(0.0, 1.0, 0.0, 1.0) : vec4(1.0, 0.0, 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !chromakey radius=2\n"
         "        !shader fragment=halves\n"
         "!window size=16;16\n"
         "    !chromakey radius=2 hue=0\n"
         "        !shader fragment=halves\n",
         2, pix);
    for (int y = 0; y < H; y += 3) {
        for (int x = 0; x <= 4; x++) {
            expect_exact(pix[0], x, y, 0x00000000u);
            expect_exact(pix[1], x, y, 0xff00ff00u);
        }
        for (int x = 11; x < W; x++) {
            expect_exact(pix[0], x, y, 0xffff0000u);
            expect_exact(pix[1], x, y, 0x00000000u);
        }
    }
}

/* !edges of a flat picture: its blur equals it, so the difference is
 * 0 light at alpha max(1, 1): opaque black everywhere, edges of the
 * picture included (the blur reads the edge colour beyond). mixer=0.5
 * lays half the original over that: (0.125, 0.25, 0.0625) at alpha 0.5 +
 * (1 - 0.5) 1 = 1. An edge, white on the left and black on the right,
 * with downsample=1 radius=2 (sigma 0.6: weights 1, w1 = exp(-1/0.72) =
 * 0.24935, w2 = exp(-4/0.72) = 0.00387, sum S = 1.50643): across, column
 * 7 blurs to (1 + w1 + w2) / S = 0.83191 and column 8 to (w1 + w2) / S,
 * both 0.16809 from the original; column 6 (1 + 2 w1 + w2) / S, 0.00256
 * off; column 5 none. Down the picture nothing changes. (colorbits=32:
 * the passes keep 32-bit floats, where a 16-bit float of 0.99744 is
 * 0.99756 or 0.99707, 8 or 10 once encoded.) With two children a
 * first pass composites them ((0, 0.25, 0, 0.5) over (0.25, 0, 0, 1):
 * (0.125, 0.25, 0, 1)) and the last reads it through `first`: flat, no
 * edges, and mixer=1 lays all of it over the black: (0.125, 0.25, 0, 1). */
static void filter_edges(void **st)
{
    (void)st;
    uint32_t pix[4][W * H];
    draw(SOLID
         "let split = '''${HEADER}\n"
         "in vec2 coord;\n"
         "out vec4 color;\n"
         "void main() {\n"
         "    color = coord.x < 0.5 ? vec4(1.0) : vec4(0.0, 0.0, 0.0, 1.0);\n"
         "}\n"
         "'''\n"
         "!window size=16;16\n"
         "    !edges radius=4\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !edges radius=4 mixer=0.5\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n"
         "!window size=16;16\n"
         "    !edges radius=2 downsample=1 colorbits=32\n"
         "        !shader fragment=split\n"
         "!window size=16;16\n"
         "    !edges radius=4 mixer=1\n"
         "        !shader fragment=solid rgba=0.25;0;0;1\n"
         "        !shader fragment=solid rgba=0;0.25;0;0.5\n",
         4, pix);
    for (int y = 0; y < H; y += 3)
        for (int x = 0; x < W; x += 3) {
            expect_exact(pix[0], x, y, 0xff000000u);
            expect(pix[1], x, y, 0.125, 0.25, 0.0625, 1, 1);
            expect(pix[3], x, y, 0.125, 0.25, 0, 1, 1);
        }
    expect_exact(pix[0], 15, 15, 0xff000000u);
    double w1 = exp(-1 / 0.72), w2 = exp(-4 / 0.72), s = 1 + 2 * (w1 + w2);
    double edge = 1 - (1 + w1 + w2) / s, near = 1 - (1 + 2 * w1 + w2) / s;
    assert_true(fabs(edge - 0.16809) < 1e-4 && fabs(near - 0.00256) < 1e-4);
    for (int y = 0; y < H; y += 5) {
        expect(pix[2], 7, y, edge, edge, edge, 1, 1);
        expect(pix[2], 8, y, edge, edge, edge, 1, 1);
        expect(pix[2], 6, y, near, near, near, 1, 1);
        expect(pix[2], 9, y, near, near, near, 1, 1);
        expect_exact(pix[2], 5, y, 0xff000000u);
        expect_exact(pix[2], 10, y, 0xff000000u);
        expect_exact(pix[2], 0, y, 0xff000000u);
    }
}

/* !flare of a picture whose luminance (0.2126 0.25 + 0.7152 0.5 +
 * 0.0722 0.125 = 0.4197) is below the threshold 1: no pixel is bright
 * (smoothstep(0, 1, l - 1) = 0), ghosts, halo and starbursts add
 * nothing, and the picture comes out as it went in. */
static void filter_flare(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    draw(SOLID
         "!window size=16;16\n"
         "    !flare\n"
         "        !shader fragment=solid rgba=0.25;0.5;0.125;1\n",
         1, pix);
    for (int y = 0; y < H; y += 3)
        for (int x = 0; x < W; x += 3) expect(pix[0], x, y, 0.25, 0.5, 0.125, 1, 1);
    expect(pix[0], 15, 15, 0.25, 0.5, 0.125, 1, 1);
}

/* !kaleid segments=4 of a ramp (red coord.x, green coord.y): the wedge
 * from 1/2 to 3/4 turn (the bottom left quarter) is the input itself
 * within the radius (8 pixels), and the others mirror it, so the picture
 * is symmetric in both axes and under the half turn that takes one
 * segment onto the one two further on. Column 3, row 11 (GL pixel 3;4,
 * 5.7 from the centre) is the input there, (3.5 / 16, 4.5 / 16). Column
 * 0, row 15 (at (-7.5, -7.5), 10.607 from the centre, ring 1) folds
 * back to 8 (2 - 10.607 / 8) = 5.393 along the same line: (-3.8137,
 * -3.8137), where the linear ramp reads (8 - 3.8137) / 16 = 0.26164. */
static void filter_kaleid(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    draw(RAMP
         "!window size=16;16\n"
         "    !kaleid segments=4\n"
         "        !shader fragment=ramp\n",
         1, pix);
    expect(pix[0], 3, 11, 3.5 / 16, 4.5 / 16, 0, 1, 1);
    expect(pix[0], 12, 11, 3.5 / 16, 4.5 / 16, 0, 1, 1);
    expect(pix[0], 3, 4, 3.5 / 16, 4.5 / 16, 0, 1, 1);
    expect(pix[0], 12, 4, 3.5 / 16, 4.5 / 16, 0, 1, 1);
    double fold = (8 - 7.5 * (8 * (2 - sqrt(2 * 7.5 * 7.5) / 8)) / sqrt(2 * 7.5 * 7.5)) / 16;
    assert_true(fabs(fold - 0.26164) < 1e-4);
    expect(pix[0], 0, 15, fold, fold, 0, 1, 1);
    int distinct = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t p = at(pix[0], x, y);
            uint32_t mirrors[3] = {at(pix[0], W - 1 - x, y), at(pix[0], x, H - 1 - y),
                                   at(pix[0], W - 1 - x, H - 1 - y)};
            for (int k = 0; k < 3; k++)
                for (int c = 0; c < 32; c += 8)
                    if (abs(chan(p, c) - chan(mirrors[k], c)) > 1)
                        fail_msg("pixel (%d,%d) %08x and its mirror %d: %08x", x, y, p, k, mirrors[k]);
            distinct += p != at(pix[0], 0, 0);
        }
    assert_true(distinct > W * H / 2);
}

/* !noise (one component, default 0.5 noise + 0.5, the other channels
 * default 1) read back by a !shader that writes its red and whether all
 * four channels are in range (red in 0..1, green, blue and alpha 1): the
 * same seed gives the same picture in two runtimes, another seed another
 * picture; every value is in range, and the noise varies. */
static void filter_noise(void **st)
{
    (void)st;
    static const char fmt[] = "let check = '''${HEADER}\n"
                              "in vec2 coord;\n"
                              "out vec4 color;\n"
                              "uniform sampler2D texture0;\n"
                              "void main() {\n"
                              "    vec4 n = texture(texture0, coord);\n"
                              "    bool ok = n.r >= 0.0 && n.r <= 1.0 && n.g == 1.0 && n.b == 1.0 && n.a == 1.0;\n"
                              "    color = vec4(n.r, ok ? 1.0 : 0.0, 0.0, 1.0);\n"
                              "}\n"
                              "'''\n"
                              "!window size=16;16\n"
                              "    !shader fragment=check\n"
                              "        !noise seed=%d scale=0.25\n";
    char script[1024];
    uint32_t a[1][W * H], b[1][W * H], c[1][W * H];
    snprintf(script, sizeof script, fmt, 1);
    draw(script, 1, a);
    draw(script, 1, b);
    snprintf(script, sizeof script, fmt, 2);
    draw(script, 1, c);
    assert_memory_equal(a[0], b[0], sizeof a[0]);
    int differ = 0, lo = 255, hi = 0;
    for (int i = 0; i < W * H; i++) {
        if ((a[0][i] & 0xff00ffffu) != 0xff00ff00u || (c[0][i] & 0xff00ffffu) != 0xff00ff00u)
            fail_msg("pixel (%d,%d): %08x / %08x, a value out of range", i % W, i / W, a[0][i], c[0][i]);
        differ += a[0][i] != c[0][i];
        int r = chan(a[0][i], 16);
        lo = r < lo ? r : lo;
        hi = r > hi ? r : hi;
    }
    assert_true(differ > W * H / 4);
    assert_true(hi - lo > 20);
}

/* }===== */

/* {===== the graph: references, sizes past the limits, the memory budget */

/* !reference shows the picture of the node with its id drawn before it
 * (docs/windows.md "!reference"): a hidden-from-nothing offscreen !shader
 * id=:src of blue, referenced from the window. */
static void reference_shows_picture(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "!offscreen size=16;16\n"
                                 "    !shader id=:src fragment=solid rgba=0;0;0.5;1\n"
                                 "!window size=16;16\n"
                                 "    !reference id=:src\n",
                                 0);
    frame(rt, 2, pix);
    expect(pix[1], 3, 3, 0, 0, 0.5, 1, 1);
    expect(pix[1], 12, 12, 0, 0, 0.5, 1, 1);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    fl_free(rt);
}

/* A !reference inside the pass it names (a cycle) shows that pass's
 * picture of the frame before, with one warning over three frames: the
 * shader gives 0.25 + 0.5 * its input, so red is 0.25 (no picture yet),
 * then 0.25 + 0.5 * 0.25 = 0.375, then 0.4375; a !reference to an id
 * that nothing has, and one without an id, each say so once and show
 * nothing. */
static void reference_cycle(void **st)
{
    (void)st;
    uint32_t pix[2][W * H];
    fl_runtime *rt = load_script("let echo = '''${HEADER}\n"
                                 "in vec2 coord;\n"
                                 "out vec4 color;\n"
                                 "uniform sampler2D texture0;\n"
                                 "void main() {\n"
                                 "    color = vec4(0.25 + 0.5 * texture(texture0, coord).r, 0.0, 0.0, 1.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=16;16\n"
                                 "    !shader id=:a fragment=echo\n"
                                 "        !reference id=:a\n"
                                 "!window size=16;16\n"
                                 "    !reference id=:nothing\n"
                                 "    !reference\n",
                                 0);
    const double red[3] = {0.25, 0.375, 0.4375};
    for (int f = 0; f < 3; f++) {
        frame(rt, 2, pix);
        expect(pix[0], 8, 8, red[f], 0, 0, 1, 1);
        expect_exact(pix[1], 8, 8, 0x00000000u);
    }
    if (count(logged, "!reference id=a is inside the pass it refers to") != 1)
        fail_msg("expected one cycle warning, log:\n%s", logged);
    if (count(logged, "!reference id=nothing: no window node drawn before it has that id") != 1)
        fail_msg("expected one warning for id=nothing, log:\n%s", logged);
    if (count(logged, "!reference without an id shows nothing") != 1)
        fail_msg("expected one warning for the reference without id, log:\n%s", logged);
    fl_free(rt);
}

/* A pass larger than the GL's framebuffer limit is refused with the
 * limit named, once; its window draws its other children and the
 * runtime goes on. */
static void size_past_limit(void **st)
{
    (void)st;
    uint32_t pix[1][W * H];
    fl_runtime *rt = load_script(SOLID
                                 "!window size=16;16\n"
                                 "    !shader fragment=solid rgba=0;0.5;0;1\n"
                                 "    !shader fragment=solid rgba=1;0;0;1 size=1000000;8\n",
                                 0);
    for (int f = 0; f < 2; f++) {
        frame(rt, 1, pix);
        expect(pix[0], 8, 8, 0, 0.5, 0, 1, 1);
    }
    if (count(logged, "framebuffer is beyond this OpenGL's limit of ") != 1)
        fail_msg("expected one limit message, log:\n%s", logged);
    fl_free(rt);
}

/* Framebuffers are charged to the memory budget (--max-memory): a
 * 4096x4096 pass of 32-bit floats (256 MiB) under a budget of 96 MiB is
 * refused with the budget named, once; the window's other child draws. */
static void framebuffer_budget(void **st)
{
    (void)st;
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(SOLID
          "!window size=16;16\n"
          "    !shader fragment=solid rgba=0;0.5;0;1\n"
          "    !shader fragment=solid rgba=1;0;0;1 size=4096;4096 colorbits=32\n",
          f);
    fclose(f);
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    o.max_memory = (size_t)96 << 20;
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_load(rt, path), 0);
    uint32_t pix[1][W * H];
    for (int k = 0; k < 2; k++) {
        frame(rt, 1, pix);
        expect(pix[0], 8, 8, 0, 0.5, 0, 1, 1);
    }
    if (count(logged, "4096x4096 framebuffer (256 MB) is past the memory budget (--max-memory)") != 1)
        fail_msg("expected one budget message, log:\n%s", logged);
    fl_free(rt);
}

/* }===== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shader_uniforms),
        cmocka_unit_test(shader_arrays),
        cmocka_unit_test(shader_alpha),
        cmocka_unit_test(engine_uniforms),
        cmocka_unit_test(shader_composite),
        cmocka_unit_test(shader_colorbits),
        cmocka_unit_test(shader_vertex),
        cmocka_unit_test(template_expressions),
        cmocka_unit_test(template_child_textures),
        cmocka_unit_test(passes_last),
        cmocka_unit_test(last_across_frames),
        cmocka_unit_test(sampler_outside),
        cmocka_unit_test(sampler_nearest),
        cmocka_unit_test(glsl_error),
        cmocka_unit_test(glsl_error_keeps_last_good),
        cmocka_unit_test(template_error),
        cmocka_unit_test(filter_adjust),
        cmocka_unit_test(filter_blur),
        cmocka_unit_test(filter_blur_other_size),
        cmocka_unit_test(filter_vignette),
        cmocka_unit_test(filter_transform),
        cmocka_unit_test(filter_feedback),
        cmocka_unit_test(filter_feedback_skipped_frames),
        cmocka_unit_test(filter_feedback_moves),
        cmocka_unit_test(filter_chromakey),
        cmocka_unit_test(filter_edges),
        cmocka_unit_test(filter_flare),
        cmocka_unit_test(filter_kaleid),
        cmocka_unit_test(filter_noise),
        cmocka_unit_test(reference_shows_picture),
        cmocka_unit_test(reference_cycle),
        cmocka_unit_test(size_past_limit),
        cmocka_unit_test(framebuffer_budget),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
