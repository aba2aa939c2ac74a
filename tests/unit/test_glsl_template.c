/* test_glsl_template.c: the shader templates (lib/render/gl/glsl_template.h),
 * Mako's subset as Flitter's shaders use it: substitutions with Python's
 * printing of ints, floats, bools and lists, Flitter vectors from node
 * attributes, control lines, loops with loop.index, includes, and every
 * error reported with its line, never a crash. Also every built-in
 * template of lib/render/gl/glsl renders for the cases the filters use. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "glsl_library.h"
#include "glsl_template.h"

typedef struct Name {
    const char *name;
    TplValue (*make)(void);
} Name;

static TplValue v_count(void) { return (TplValue){vec_num1(3), TPL_VEC}; }
static TplValue v_offset(void)
{
    double x[2] = {-3, 4.5};
    return (TplValue){vec_from_nums(x, 2), TPL_VEC};
}
static TplValue v_passes(void) { return (TplValue){vec_num1(5), TPL_INT}; }
static TplValue v_composite(void) { return (TplValue){vec_str("over", 4), TPL_STR}; }
static TplValue v_children(void)
{
    Vec *p[2] = {vec_str("texture0", 8), vec_str("texture1", 8)};
    return (TplValue){vec_compose_take(p, 2), TPL_LIST};
}
static TplValue v_none(void) { return (TplValue){NULL, TPL_NONE}; }
static TplValue v_header(void) { return (TplValue){vec_str("#version 330\n", 13), TPL_STR}; }

static const Name names[] = {{"count", v_count}, {"offset", v_offset}, {"passes", v_passes},
                             {"composite", v_composite}, {"child_textures", v_children},
                             {"tonemap_function", v_none}, {"HEADER", v_header}};

static bool lookup(void *ctx, const char *name, size_t len, TplValue *out)
{
    (void)ctx;
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (strlen(names[i].name) == len && memcmp(names[i].name, name, len) == 0) {
            *out = names[i].make();
            return true;
        }
    return false;
}

static const char *lib(const char *file)
{
    if (strcmp(file, "one.glsl") == 0) return "one ${count}\n";
    if (strcmp(file, "loop.glsl") == 0) return "% include_me = 1\n";
    return glsl_library(file);
}

static char out_text[8192];
static char err_text[400];

/* Render [src]; returns its rc, the text in out_text, the error in err_text. */
static int render(const char *src)
{
    TplEnv env = {.lookup = lookup, .include = lib};
    Buf out = BUF_INIT;
    Buf err = BUF_INIT;
    int rc = tpl_render(src, strlen(src), &env, &out, &err);
    snprintf(out_text, sizeof out_text, "%s", out.data ? out.data : "");
    snprintf(err_text, sizeof err_text, "%s", buf_line(&err));
    buf_free(&out);
    buf_free(&err);
    return rc;
}

static void expect(const char *src, const char *want)
{
    int rc = render(src);
    if (rc != 0) fail_msg("%s: error %s", src, err_text);
    if (strcmp(out_text, want) != 0) fail_msg("%s: gave [%s], want [%s]", src, out_text, want);
}

static void expect_error(const char *src, const char *want)
{
    assert_int_equal(render(src), -1);
    if (!strstr(err_text, want)) fail_msg("%s: error [%s], want [%s]", src, err_text, want);
}

static void substitutions(void **st)
{
    (void)st;
    expect("x ${count} y\n", "x 3 y\n");
    expect("${int(count)}/${float(count)}\n", "3/3.0\n");
    expect("vec2(${float(offset[0])}, ${float(offset[1])})\n", "vec2(-3.0, 4.5)\n");
    expect("${passes - 4} ${passes / 2} ${passes // 2} ${passes % 3} ${2 ** 3}\n", "1 2.5 2 2 8\n");
    expect("${'last' if passes == 5 else 'texture0'}\n", "last\n");
    expect("${'last' if passes == 4 else 'texture0'}\n", "texture0\n");
    expect("${composite}_${len(child_textures)} ${child_textures[1]} ${child_textures[-2]}\n",
           "over_2 texture1 texture0\n");
    expect("${passes > 1 and passes < 6} ${not passes} ${None} ${tonemap_function or 'none'}\n",
           "True False None none\n");
    expect("${'cyl' in ('cylinder', 'sphere')} ${'sphere' in ('cylinder', 'sphere')} ${'ph' in 'alpha'}\n",
           "False True True\n");
    /* a node attribute is a Flitter vector: arithmetic element-wise, printed as the language prints */
    expect("${offset * 2} ${count + 0.5} ${count == 3} ${offset[0] < 0}\n", "-69 3.5 True True\n");
    expect("${min(2, passes)} ${max(count, 7)} ${abs(-2.5)} ${str(count)}!\n", "2 7 2.5 3!\n");
    expect("no braces here $ {x}\n", "no braces here $ {x}\n");
    expect("${\"}\"} and ${'{'}\n", "} and {\n");
}

static void control(void **st)
{
    (void)st;
    expect("a\n% if passes == 5:\nfive\n% elif passes == 4:\nfour\n% else:\nother\n% endif\nb\n", "a\nfive\nb\n");
    expect("% if passes == 4:\nfour\n% elif passes > 4:\nmore\n% endif\n", "more\n");
    expect("% if not child_textures:\nnone\n% else:\nsome\n% endif\n", "some\n");
    expect("% for name in child_textures:\n${loop.index}:${name}${',' if not loop.last else ''}\n% endfor\n",
           "0:texture0,\n1:texture1\n");
    expect("% for i in (1, 2):\n%   for j in (3, 4):\n${i}${j}\n%   endfor\n% endfor\n", "13\n14\n23\n24\n");
    expect("## a comment\n%% literal\nx\\\ny\n", "% literal\nxy\n");
    expect("<%include file=\"one.glsl\"/>\nafter\n", "one 3\nafter\n");
}

static void errors(void **st)
{
    (void)st;
    expect_error("a\n${nothing}\n", "line 2: name 'nothing' is not defined");
    expect_error("% if passes:\nx\n", "line 1: block not closed");
    expect_error("x\n% endif\n", "line 2: endif without if");
    expect_error("% endfor\n", "endfor without for");
    expect_error("${passes +}\n", "line 1: expression ends too soon");
    expect_error("${count[5]}\n", "index out of range");
    expect_error("${(1, 2) + 'a'}\n", "not numbers");
    expect_error("${loop.index}\n", "not supported");
    expect_error("${unknown_fn(1)}\n", "unknown function");
    expect_error("<%include file=\"missing.glsl\"/>\n", "no include file \"missing.glsl\"");
    expect_error("<% x = 1 %>\n", "unsupported template tag");
    expect_error("% while True:\n", "unsupported control line");
    expect_error("${'open\n", "not closed");
    /* nesting past the limit is refused, not recursed into */
    char deep[64 * 14 + 64 * 10 + 16] = "";
    for (int i = 0; i < 65; i++) strcat(deep, "% if 1:\n");
    expect_error(deep, "nested deeper than 64");
}

/* Every built-in template renders for the cases its filter uses. */
static void library(void **st)
{
    (void)st;
    static const char *const files[] = {"default.vert", "default.frag", "adjust.frag", "blur.frag", "bloom.frag",
                                        "chromakey.frag", "edges.frag", "feedback.frag", "flare.frag", "kaleid.frag",
                                        "transform.frag", "vignette.frag", "video.vert", "video.frag"};
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        const char *src = glsl_library(files[i]);
        assert_non_null(src);
        TplEnv env = {.lookup = lookup, .include = glsl_library};
        Buf out = BUF_INIT;
        /* templates that need names the test does not give fail with a message, never otherwise */
        Buf err = BUF_INIT;
        int rc = tpl_render(src, strlen(src), &env, &out, &err);
        if (rc != 0 && !strstr(buf_cstr(&err), "is not defined")) fail_msg("%s: %s", files[i], buf_cstr(&err));
        if (rc == 0) assert_non_null(strstr(out.data, "#version 330"));
        buf_free(&out);
        buf_free(&err);
    }
    assert_null(glsl_library("no_such.frag"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(substitutions),
        cmocka_unit_test(control),
        cmocka_unit_test(errors),
        cmocka_unit_test(library),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
