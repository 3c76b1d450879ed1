# SPDX-License-Identifier: GPL-3.0-or-later
"""The mutation operators on small C texts: each proposes exactly the change its description
says, and nothing in comments, strings or preprocessor lines but the tolerances' macros."""

import math

from mutate.operators import DEFAULT_OPERATORS, OPERATORS, generate


def mutated(text, op):
    return [m.mutated for m in generate("src/x.c", text, operators=(op,))]


def test_rel_flips_one_comparison_per_line():
    assert mutated("int f(int a, int b) { return a < b; }\n", "rel") == [
        "int f(int a, int b) { return a <= b; }"
    ]


def test_status_makes_a_failure_success():
    text = "int f(void) { return SDAE_ERR_MASS; }\n"
    assert mutated(text, "status") == ["int f(void) { return SDAE_OK; }"]


def test_nothing_lands_in_comments_strings_or_preprocessor_lines():
    text = '#define N 3\n/* a < b */\nconst char *s = "a < b";\nint f(int a) { return a + 1; }\n'
    for op in DEFAULT_OPERATORS:
        for m in generate("src/x.c", text, operators=(op,)):
            assert m.line == 4, (op, m.mutated)


def test_digits_moves_a_long_coefficient_two_ulps_up():
    text = "static const double a[] = {5.26001519587677318785587544488e-2, 0.5};\n"
    ms = generate("src/x.c", text, operators=("digits",))
    assert len(ms) == 1  # 0.5 has one significant digit: not a coefficient
    v = 5.26001519587677318785587544488e-2
    new = float(ms[0].replacement)
    assert new == math.nextafter(math.nextafter(v, math.inf), math.inf)
    assert new != v


def test_carve_takes_one_element_short_in_calls_alone():
    text = (
        "double *sdae__take(sdae_arena *a, size_t n1, size_t n2);\n"
        "void carve(sdae_arena *a, size_t n) { x = sdae__take(a, 2 * n, 1); }\n"
        "static size_t midpoint_scratch(const sdae_model *m) { return m->n_mu; }\n"
        "static size_t other(const sdae_model *m) { return m->n_mu; }\n"
    )
    assert mutated(text, "carve") == [
        "void carve(sdae_arena *a, size_t n) { x = sdae__take(a, (2 * n) - 1, 1); }",
        "static size_t midpoint_scratch(const sdae_model *m) { return (m->n_mu) - 1; }",
    ]


def test_tol_makes_tolerances_zero():
    text = (
        "#define NEWTON_SMALL 1e-10\n#define XI_ROUNDING (2.0 * DBL_EPSILON)\n"
        "#define COUNT 4\n"
        "int f(double x) { double tol = 4 * x, y = 1.0; o.newton_tol = 3.0; return 0; }\n"
    )
    assert mutated(text, "tol") == [
        "#define NEWTON_SMALL 0.0",
        "#define XI_ROUNDING 0.0",
        "int f(double x) { double tol = 0.0, y = 1.0; o.newton_tol = 3.0; return 0; }",
    ]


def test_carve_is_left_to_sanitized_campaigns():
    assert "carve" in OPERATORS and "carve" not in DEFAULT_OPERATORS
    assert {"digits", "tol"} <= set(DEFAULT_OPERATORS)


def test_ids_survive_edits_elsewhere_in_the_file():
    body = "int f(int a, int b) { return a < b; }\n"
    before = generate("src/x.c", body, operators=("rel",))[0]
    after = generate("src/x.c", "/* moved down */\nint g;\n" + body, operators=("rel",))[0]
    assert before.id == after.id and after.line == before.line + 2
