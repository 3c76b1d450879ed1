/* SPDX-License-Identifier: GPL-3.0-or-later */
/* A small FMI importer of our own, run under the sanitizers and valgrind (ctest label fmi): it
 * loads an FMU's binary with dlopen, as an importer does, and drives it through instantiation,
 * bad input of every kind, steps, roll-back, a failing step, reset and free, checking each
 * status, that every refusal comes with a message through the logger, and that nothing the FMU
 * was asked to keep changed.
 *   fmi_importer 3|2 DIR NAME
 * DIR is the unpacked FMU (modelDescription.xml, binaries/<platform>/NAME.so). The value
 * references are read from modelDescription.xml by name. Exit status 0 when every check holds. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"

static int failures;
#define CHECK(cond)                                                                                \
  do {                                                                                             \
    if (!(cond)) {                                                                                 \
      fprintf(stderr, "importer:%d: check failed: %s\n", __LINE__, #cond);                         \
      failures++;                                                                                  \
    }                                                                                              \
  } while (0)

/* ---- the model description ----------------------------------------------------------------- */

static char *read_text(const char *path) {
  FILE *f = fopen(path, "rb");
  char *text;
  long n;
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  n = ftell(f);
  fseek(f, 0, SEEK_SET);
  text = calloc((size_t)n + 1, 1);
  if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
    free(text);
    text = NULL;
  }
  fclose(f);
  return text;
}

/* the value reference of the variable name (as the describer writes it: name, then
 * valueReference) */
static unsigned vr_of(const char *xml, const char *name) {
  char key[80];
  const char *at;
  snprintf(key, sizeof key, "name=\"%s\" valueReference=\"", name);
  if (!(at = strstr(xml, key))) {
    fprintf(stderr, "importer: no variable %s\n", name);
    exit(2);
  }
  return (unsigned)strtoul(at + strlen(key), NULL, 10);
}

/* the attribute's value (instantiationToken or guid) into out */
static void attribute(const char *xml, const char *attr, char *out, size_t len) {
  char key[40];
  const char *at, *end;
  snprintf(key, sizeof key, "%s=\"", attr);
  at = strstr(xml, key);
  if (!at || !(end = strchr(at + strlen(key), '"')) || (size_t)(end - at) >= len) exit(2);
  at += strlen(key);
  memcpy(out, at, (size_t)(end - at));
  out[end - at] = '\0';
}

/* ---- one FMI version behind a few calls ---------------------------------------------------- */

/* what the logger saw: the calls with an error status since the last look; messages that were
 * empty or did not name the instance (FMI 2.0's instanceName; FMI 3.0's logger has no such
 * argument, the message begins with it) */
#define INSTANCE "importer"
static int errors_logged;
static int messages_empty;
static int messages_unnamed;

static void note(int error, const char *message, int named) {
  if (error) errors_logged++;
  if (!message || !*message) messages_empty++;
  if (!named) {
    fprintf(stderr, "importer: a message without the instance's name: %s\n", message);
    messages_unnamed++;
  }
}

static void logger3(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category,
                    fmi3String message) {
  (void)env, (void)category;
  note(status == fmi3Error, message,
       message && strncmp(message, INSTANCE ": ", strlen(INSTANCE ": ")) == 0);
}

static void logger2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                    fmi2String category, fmi2String message, ...) {
  (void)env, (void)category;
  note(status == fmi2Error, message, name && strcmp(name, INSTANCE) == 0);
}

/* FMI 2.0's memory callbacks, counted: every block given back */
static long live_blocks;
static void *alloc2(size_t n, size_t size) {
  void *p = calloc(n, size);
  if (p) live_blocks++;
  return p;
}
static void free2(void *p) {
  if (p) live_blocks--;
  free(p);
}

typedef struct fmu {
  int version;
  void *dll;
  void *instance;
  char token[64];
} fmu;

/* the FMU's function `name` (a data pointer copied into a function pointer, as POSIX allows) */
typedef void (*fn)(void);
static fn sym(const fmu *f, const char *name) {
  void *s = dlsym(f->dll, name);
  fn p;
  if (!s) {
    fprintf(stderr, "importer: the FMU has no %s\n", name);
    exit(2);
  }
  memcpy(&p, &s, sizeof p);
  return p;
}
#define SYM(f, name) sym(f, name)

/* the status as 0 (OK) or not: fmi3OK and fmi2OK are both 0 */
typedef int status_t;

static void *instantiate(fmu *f, const char *token) {
  if (f->version == 3) {
    fmi3InstantiateCoSimulationTYPE *inst =
        (fmi3InstantiateCoSimulationTYPE *)SYM(f, "fmi3InstantiateCoSimulation");
    return inst(INSTANCE, token, NULL, fmi3False, fmi3True, fmi3False, fmi3False, NULL, 0, NULL,
                logger3, NULL);
  } else {
    static const fmi2CallbackFunctions cb = {logger2, alloc2, free2, NULL, NULL};
    fmi2InstantiateTYPE *inst = (fmi2InstantiateTYPE *)SYM(f, "fmi2Instantiate");
    return inst(INSTANCE, fmi2CoSimulation, token, NULL, &cb, fmi2False, fmi2True);
  }
}

static void free_instance(fmu *f) {
  if (f->version == 3)
    ((fmi3FreeInstanceTYPE *)SYM(f, "fmi3FreeInstance"))(f->instance);
  else
    ((fmi2FreeInstanceTYPE *)SYM(f, "fmi2FreeInstance"))(f->instance);
  f->instance = NULL;
}

static status_t enter_init(fmu *f) {
  if (f->version == 3)
    return ((fmi3EnterInitializationModeTYPE *)SYM(f, "fmi3EnterInitializationMode"))(
        f->instance, fmi3False, 0.0, 0.0, fmi3False, 0.0);
  if (((fmi2SetupExperimentTYPE *)SYM(f, "fmi2SetupExperiment"))(f->instance, fmi2False, 0.0, 0.0,
                                                                 fmi2False, 0.0) != fmi2OK)
    return -1;
  return ((fmi2EnterInitializationModeTYPE *)SYM(f, "fmi2EnterInitializationMode"))(f->instance);
}

static status_t exit_init(fmu *f) {
  if (f->version == 3)
    return ((fmi3ExitInitializationModeTYPE *)SYM(f, "fmi3ExitInitializationMode"))(f->instance);
  return ((fmi2ExitInitializationModeTYPE *)SYM(f, "fmi2ExitInitializationMode"))(f->instance);
}

static status_t do_step(fmu *f, double t, double h) {
  if (f->version == 3) {
    fmi3Boolean event, terminate, early;
    fmi3Float64 last;
    return ((fmi3DoStepTYPE *)SYM(f, "fmi3DoStep"))(f->instance, t, h, fmi3False, &event,
                                                    &terminate, &early, &last);
  }
  return ((fmi2DoStepTYPE *)SYM(f, "fmi2DoStep"))(f->instance, t, h, fmi2False);
}

static status_t reset(fmu *f) {
  if (f->version == 3) return ((fmi3ResetTYPE *)SYM(f, "fmi3Reset"))(f->instance);
  return ((fmi2ResetTYPE *)SYM(f, "fmi2Reset"))(f->instance);
}

static status_t terminate(fmu *f) {
  if (f->version == 3) return ((fmi3TerminateTYPE *)SYM(f, "fmi3Terminate"))(f->instance);
  return ((fmi2TerminateTYPE *)SYM(f, "fmi2Terminate"))(f->instance);
}

static status_t get_real(fmu *f, const unsigned *vr, size_t n, double *x) {
  if (f->version == 3)
    return ((fmi3GetFloat64TYPE *)SYM(f, "fmi3GetFloat64"))(f->instance, vr, n, x, n);
  return ((fmi2GetRealTYPE *)SYM(f, "fmi2GetReal"))(f->instance, vr, n, x);
}

static status_t set_real(fmu *f, unsigned vr, double x) {
  if (f->version == 3)
    return ((fmi3SetFloat64TYPE *)SYM(f, "fmi3SetFloat64"))(f->instance, &vr, 1, &x, 1);
  return ((fmi2SetRealTYPE *)SYM(f, "fmi2SetReal"))(f->instance, &vr, 1, &x);
}

static status_t set_string(fmu *f, unsigned vr, const char *s) {
  if (f->version == 3)
    return ((fmi3SetStringTYPE *)SYM(f, "fmi3SetString"))(f->instance, &vr, 1, &s, 1);
  return ((fmi2SetStringTYPE *)SYM(f, "fmi2SetString"))(f->instance, &vr, 1, &s);
}

static status_t set_logging(fmu *f, int on, const char *category) {
  size_t n = category ? 1 : 0;
  if (f->version == 3)
    return ((fmi3SetDebugLoggingTYPE *)SYM(f, "fmi3SetDebugLogging"))(f->instance, on, n,
                                                                      &category);
  return ((fmi2SetDebugLoggingTYPE *)SYM(f, "fmi2SetDebugLogging"))(f->instance, on, n, &category);
}

static status_t get_state(fmu *f, void **state) {
  if (f->version == 3)
    return ((fmi3GetFMUStateTYPE *)SYM(f, "fmi3GetFMUState"))(f->instance, state);
  return ((fmi2GetFMUstateTYPE *)SYM(f, "fmi2GetFMUstate"))(f->instance, state);
}

static status_t set_state(fmu *f, void *state) {
  if (f->version == 3)
    return ((fmi3SetFMUStateTYPE *)SYM(f, "fmi3SetFMUState"))(f->instance, state);
  return ((fmi2SetFMUstateTYPE *)SYM(f, "fmi2SetFMUstate"))(f->instance, state);
}

static status_t free_state(fmu *f, void **state) {
  if (f->version == 3)
    return ((fmi3FreeFMUStateTYPE *)SYM(f, "fmi3FreeFMUState"))(f->instance, state);
  return ((fmi2FreeFMUstateTYPE *)SYM(f, "fmi2FreeFMUstate"))(f->instance, state);
}

/* the state serialized by f and read back by g (f itself, or another instance) into *out, the
 * last `cut` bytes cut off and the byte at `flip` (when < size) inverted */
static status_t round_trip_cut(fmu *f, fmu *g, void *state, void **out, size_t cut, size_t flip) {
  size_t size = 0;
  unsigned char *bytes;
  status_t rc;
  if (f->version == 3) {
    if (((fmi3SerializedFMUStateSizeTYPE *)SYM(f, "fmi3SerializedFMUStateSize"))(f->instance, state,
                                                                                 &size) != fmi3OK)
      return -1;
    if (!(bytes = malloc(size))) return -1;
    rc = ((fmi3SerializeFMUStateTYPE *)SYM(f, "fmi3SerializeFMUState"))(f->instance, state, bytes,
                                                                        size);
    if (flip < size) bytes[flip] = (unsigned char)~bytes[flip];
    size = cut < size ? size - cut : 0;
    if (rc == fmi3OK)
      rc = ((fmi3DeserializeFMUStateTYPE *)SYM(g, "fmi3DeserializeFMUState"))(g->instance, bytes,
                                                                              size, out);
  } else {
    if (((fmi2SerializedFMUstateSizeTYPE *)SYM(f, "fmi2SerializedFMUstateSize"))(f->instance, state,
                                                                                 &size) != fmi2OK)
      return -1;
    if (!(bytes = malloc(size))) return -1;
    rc = ((fmi2SerializeFMUstateTYPE *)SYM(f, "fmi2SerializeFMUstate"))(f->instance, state,
                                                                        (fmi2Byte *)bytes, size);
    if (flip < size) bytes[flip] = (unsigned char)~bytes[flip];
    size = cut < size ? size - cut : 0;
    if (rc == fmi2OK)
      rc = ((fmi2DeSerializeFMUstateTYPE *)SYM(g, "fmi2DeSerializeFMUstate"))(
          g->instance, (const fmi2Byte *)bytes, size, out);
  }
  free(bytes);
  return rc;
}

/* the size of a state's serialization; 0 when it is refused */
static size_t state_size(fmu *f, void *state) {
  size_t size = 0;
  if (f->version == 3)
    (void)((fmi3SerializedFMUStateSizeTYPE *)SYM(f, "fmi3SerializedFMUStateSize"))(f->instance,
                                                                                   state, &size);
  else
    (void)((fmi2SerializedFMUstateSizeTYPE *)SYM(f, "fmi2SerializedFMUstateSize"))(f->instance,
                                                                                   state, &size);
  return size;
}

static status_t round_trip(fmu *f, fmu *g, void *state, void **out) {
  return round_trip_cut(f, g, state, out, 0, (size_t)-1);
}

/* ---- the scenarios ------------------------------------------------------------------------- */

#define MAXOUT 64

typedef struct vars {
  unsigned T, delta, epsilon, map, q0_1, u1, q1, time;
  unsigned out[MAXOUT]; /* q, v, lambda, max_abs_c (and energy) */
  size_t n_out;
} vars;

/* the call refused with an error status and a message, nothing else changed */
static void refused(status_t rc, const char *what) {
  if (rc == 0 || errors_logged == 0)
    fprintf(stderr, "importer: %s: status %d, %d error messages\n", what, rc, errors_logged);
  CHECK(rc != 0);
  CHECK(errors_logged > 0);
  errors_logged = 0;
}

static void bad_parameters(fmu *f, const vars *v) {
  double T0, T1;
  unsigned nowhere = 1000000;
  CHECK(get_real(f, &v->T, 1, &T0) == 0);
  refused(set_real(f, v->T, 0.0), "T = 0");
  refused(set_real(f, v->T, -1e-3), "T < 0");
  refused(set_real(f, v->T, NAN), "T = NaN");
  refused(set_real(f, v->T, INFINITY), "T = Inf");
  refused(set_real(f, v->delta, 0.0), "delta = 0");
  refused(set_real(f, v->epsilon, -1.0), "epsilon < 0");
  refused(set_string(f, v->map, "nosuchmap"), "map unknown");
  refused(set_string(f, v->map, NULL), "map NULL");
  refused(set_real(f, v->q0_1, NAN), "q0[1] = NaN");
  refused(set_real(f, v->u1, NAN), "u[1] = NaN");
  refused(set_real(f, nowhere, 1.0), "no such value reference (set)");
  refused(get_real(f, &nowhere, 1, &T1), "no such value reference (get)");
  refused(set_real(f, v->q1, 1.0), "an output set");
  CHECK(get_real(f, &v->T, 1, &T1) == 0);
  CHECK(memcmp(&T0, &T1, sizeof T0) == 0); /* every refusal left T as it was */
}

static void wrong_states(fmu *f) {
  refused(do_step(f, 0.0, 1e-3), "doStep before initialization");
  refused(exit_init(f), "exitInitializationMode before enterInitializationMode");
  refused(terminate(f), "terminate before initialization");
}

static void outputs(fmu *f, const vars *v, double *x) {
  CHECK(get_real(f, v->out, v->n_out, x) == 0);
}

/* f's state, serialized, into a second instance g: g continues from the same point with a
 * stepper of its own, its next step agreeing with f's to Newton's tolerance (1e-12 on mu); the
 * state's time and variables come along bit for bit */
static void another_instance(fmu *f, const vars *v) {
  fmu g = *f;
  void *state = NULL, *copy = NULL;
  double a[MAXOUT], b[MAXOUT], t, t_g;
  CHECK(get_real(f, &v->time, 1, &t) == 0);
  CHECK(get_state(f, &state) == 0);
  CHECK((g.instance = instantiate(&g, g.token)) != NULL);
  if (!g.instance) return;
  CHECK(enter_init(&g) == 0);
  CHECK(exit_init(&g) == 0);
  CHECK(round_trip(f, &g, state, &copy) == 0);
  CHECK(set_state(&g, copy) == 0);
  CHECK(get_real(&g, &v->time, 1, &t_g) == 0 && t_g == t);
  outputs(f, v, a);
  outputs(&g, v, b);
  CHECK(memcmp(a, b, v->n_out * sizeof *a) == 0);
  CHECK(do_step(f, t, 1e-2) == 0);
  CHECK(do_step(&g, t, 1e-2) == 0);
  outputs(f, v, a);
  outputs(&g, v, b);
  for (size_t i = 0; i < v->n_out; i++) CHECK(fabs(a[i] - b[i]) <= 1e-8 * (1.0 + fabs(a[i])));
  CHECK(free_state(f, &state) == 0);
  CHECK(free_state(&g, &copy) == 0);
  free_instance(&g);
}

/* get the state, step, set it back, step again: the same bits; through serialization too */
static void roll_back(fmu *f, const vars *v, double t, double h) {
  double a[MAXOUT], b[MAXOUT], c[MAXOUT];
  void *state = NULL, *copy = NULL;
  CHECK(get_state(f, &state) == 0);
  CHECK(do_step(f, t, h) == 0);
  outputs(f, v, a);
  CHECK(set_state(f, state) == 0);
  CHECK(do_step(f, t, h) == 0);
  outputs(f, v, b);
  CHECK(memcmp(a, b, v->n_out * sizeof *a) == 0);
  CHECK(round_trip(f, f, state, &copy) == 0);
  CHECK(set_state(f, copy) == 0);
  CHECK(do_step(f, t, h) == 0);
  outputs(f, v, c);
  CHECK(memcmp(a, c, v->n_out * sizeof *a) == 0);
  CHECK(free_state(f, &copy) == 0 && copy == NULL);
  /* a state cut short, or with its header spoiled, is refused */
  refused(round_trip_cut(f, f, state, &copy, 8, (size_t)-1), "a serialized state cut short");
  CHECK(copy == NULL);
  refused(round_trip_cut(f, f, state, &copy, 0, 0), "a serialized state spoiled");
  CHECK(copy == NULL);
  /* one byte spoiled anywhere (the header's clock, the variables, the stepper's bytes) is
   * refused, and the state the importer passed in stays as it was, usable */
  CHECK(round_trip(f, f, state, &copy) == 0 && copy != NULL);
  size_t size = state_size(f, state);
  CHECK(size > 0);
  for (size_t k = 1; k < 16; k++) {
    void *kept = copy;
    refused(round_trip_cut(f, f, state, &copy, 0, k * size / 16), "a state spoiled inside");
    CHECK(copy == kept);
  }
  CHECK(set_state(f, copy) == 0);
  CHECK(do_step(f, t, h) == 0);
  outputs(f, v, c);
  CHECK(memcmp(a, c, v->n_out * sizeof *a) == 0);
  CHECK(free_state(f, &copy) == 0 && copy == NULL);
  CHECK(free_state(f, &state) == 0 && state == NULL);
}

/* a set of u reaches the outputs at the next get, without a step: some output (lambda) moves,
 * q[1] does not, and u set back gives the outputs of before bit for bit (computed again at the
 * same state and inputs) */
static void inputs_reach_outputs(fmu *f, const vars *v) {
  double before[MAXOUT], pushed[MAXOUT], back[MAXOUT];
  int moved = 0;
  outputs(f, v, before);
  CHECK(set_real(f, v->u1, 0.5) == 0);
  outputs(f, v, pushed);
  for (size_t i = 0; i < v->n_out; i++) moved |= pushed[i] != before[i];
  CHECK(moved);
  CHECK(memcmp(&pushed[0], &before[0], sizeof *before) == 0); /* q[1] */
  CHECK(set_real(f, v->u1, 0.0) == 0);
  outputs(f, v, back);
  CHECK(memcmp(back, before, v->n_out * sizeof *back) == 0);
}

/* a step that fails (a force of 1e200 leaves the state finite nowhere): an error, the outputs
 * of the last good point, every later call answered, then reset and a new run */
static void failure(fmu *f, const vars *v, double t) {
  double before[MAXOUT], after[MAXOUT], time;
  outputs(f, v, before);
  CHECK(set_real(f, v->u1, 1e200) == 0);
  refused(do_step(f, t, 1e-2), "a failing step");
  outputs(f, v, after);
  CHECK(memcmp(before, after, v->n_out * sizeof *after) == 0);
  CHECK(get_real(f, &v->time, 1, &time) == 0 && fabs(time - t) <= 1e-12);
  refused(do_step(f, t, 1e-2), "doStep after a failure");
  refused(set_real(f, v->u1, 0.0), "an input after a failure");
  CHECK(reset(f) == 0);
  CHECK(enter_init(f) == 0);
  CHECK(exit_init(f) == 0);
  CHECK(do_step(f, 0.0, 1e-2) == 0);
}

static void run(fmu *f, const vars *v) {
  double x[MAXOUT], y[MAXOUT];
  void *none;
  errors_logged = 0;
  /* a token that is not the binary's */
  none = instantiate(f, "{00000000-0000-0000-0000-000000000000}");
  CHECK(none == NULL);
  CHECK(errors_logged > 0);
  errors_logged = 0;
  CHECK((f->instance = instantiate(f, f->token)) != NULL);
  if (!f->instance) return;
  refused(set_logging(f, 1, "logNoSuchCategory"), "an unknown log category");
  CHECK(set_logging(f, 1, "logInfo") == 0);
  wrong_states(f);
  bad_parameters(f, v);
  CHECK(enter_init(f) == 0);
  outputs(f, v, x); /* initialization mode: the outputs at the start, as after it */
  CHECK(exit_init(f) == 0);
  outputs(f, v, y);
  CHECK(memcmp(x, y, v->n_out * sizeof *x) == 0);
  refused(set_real(f, v->T, 2e-3), "a fixed parameter in step mode");
  refused(do_step(f, 0.0, 0.0), "h = 0");
  refused(do_step(f, 0.0, -1e-3), "h < 0");
  refused(do_step(f, 0.0, NAN), "h = NaN");
  refused(do_step(f, 0.0, INFINITY), "h = Inf");
  refused(do_step(f, 0.0, 1e300), "h of more than 2^53 steps of T");
  refused(do_step(f, 0.5, 1e-3), "a communication point that is not the FMU's time");
  for (int i = 0; i < 10; i++) CHECK(do_step(f, i * 1e-2, 1e-2) == 0);
  CHECK(do_step(f, 0.1, 0.0025) == 0); /* not a multiple of T = 1e-3: equal substeps */
  outputs(f, v, x);
  for (size_t i = 0; i < v->n_out; i++) CHECK(isfinite(x[i]));
  inputs_reach_outputs(f, v);
  roll_back(f, v, 0.1025, 1e-2);
  another_instance(f, v);
  failure(f, v, 0.1225);
  CHECK(terminate(f) == 0);
  CHECK(reset(f) == 0);
  free_instance(f);
  CHECK(messages_empty == 0);
  CHECK(messages_unnamed == 0);
  if (f->version == 2) CHECK(live_blocks == 0);
}

static void find_vars(const char *xml, vars *v) {
  char name[32];
  v->time = vr_of(xml, "time");
  v->T = vr_of(xml, "T");
  v->delta = vr_of(xml, "delta");
  v->epsilon = vr_of(xml, "epsilon");
  v->map = vr_of(xml, "map");
  v->q0_1 = vr_of(xml, "q0[1]");
  v->u1 = vr_of(xml, "u[1]");
  v->q1 = vr_of(xml, "q[1]");
  /* the outputs are the last value references, from q[1] on */
  v->n_out = 0;
  for (unsigned vr = v->q1; v->n_out < MAXOUT; vr++) {
    snprintf(name, sizeof name, "valueReference=\"%u\"", vr);
    if (!strstr(xml, name)) break;
    v->out[v->n_out++] = vr;
  }
}

int main(int argc, char **argv) {
  char path[4096];
  fmu f = {0};
  vars v;
  char *xml;
  if (argc != 4 || (strcmp(argv[1], "3") != 0 && strcmp(argv[1], "2") != 0)) {
    fprintf(stderr, "usage: fmi_importer 3|2 DIR NAME\n");
    return 2;
  }
  f.version = atoi(argv[1]);
  snprintf(path, sizeof path, "%s/modelDescription.xml", argv[2]);
  if (!(xml = read_text(path))) {
    fprintf(stderr, "importer: cannot read %s\n", path);
    return 2;
  }
  attribute(xml, f.version == 3 ? "instantiationToken" : "guid", f.token, sizeof f.token);
  find_vars(xml, &v);
  free(xml);
  snprintf(path, sizeof path, "%s/binaries/%s/%s.so", argv[2],
           f.version == 3 ? "x86_64-linux" : "linux64", argv[3]);
  if (!(f.dll = dlopen(path, RTLD_NOW | RTLD_LOCAL))) {
    fprintf(stderr, "importer: %s\n", dlerror());
    return 2;
  }
  run(&f, &v);
  dlclose(f.dll);
  if (failures) fprintf(stderr, "importer: %d checks failed\n", failures);
  return failures ? 1 : 0;
}
