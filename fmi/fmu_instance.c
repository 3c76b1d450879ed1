/* SPDX-License-Identifier: GPL-3.0-or-later */
#include "fmu_instance.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- memory, through the instance's allocator ---------------------------------------------- */

void *fmu_mem_get(const sdae_allocator *a, size_t size) {
  void *p = a->alloc && a->free ? a->alloc(a->ud, size) : malloc(size);
  if (p) memset(p, 0, size);
  return p;
}

void fmu_mem_put(const sdae_allocator *a, void *p, size_t size) {
  if (!p) return;
  if (a->alloc && a->free)
    a->free(a->ud, p, size);
  else
    free(p);
}

/* ---- messages ------------------------------------------------------------------------------ */

/* the message through log, with the instance's name: errors and warnings always, information
 * when info is on */
static void vlog(fmu_logger log, void *env, const char *instance, int info, fmu_status status,
                 const char *fmt, va_list ap) {
  static const char *const category[] = {"logInfo", "logStatusWarning", "logStatusWarning",
                                         "logStatusError", "logStatusError"};
  char msg[512];
  if (!log || (status == FMU_OK && !info)) return;
  vsnprintf(msg, sizeof msg, fmt, ap);
  /* FMI 2.0's logger takes the message as a format: none of ours holds a conversion */
  for (char *c = msg; *c; c++)
    if (*c == '%') *c = '#';
  log(env, instance, status, category[status], msg);
}

void fmu_log(const fmu_instance *fi, fmu_status status, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vlog(fi->log, fi->env, fi->name, fi->logging_on, status, fmt, ap);
  va_end(ap);
}

/* an error before the instance holds its name (out of memory for it) */
static void early_error(fmu_logger log, void *env, const char *instance, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vlog(log, env, instance, 0, FMU_ERROR, fmt, ap);
  va_end(ap);
}

/* Errors and warnings always reach the logger (a refused call names its reason); the info
 * messages follow logging on or off, for every category (n = 0) or when logInfo is named. */
fmu_status fmu_set_logging(fmu_instance *fi, int on, size_t n, const char *const *categories) {
  static const char *const known[] = {"logStatusError", "logStatusWarning", "logInfo"};
  int info = n == 0;
  for (size_t i = 0; i < n; i++) {
    int found = 0;
    for (size_t k = 0; k < sizeof known / sizeof *known; k++)
      found |= categories && categories[i] && strcmp(categories[i], known[k]) == 0;
    if (!found) {
      fmu_log(fi, FMU_ERROR, "setDebugLogging: no log category \"%s\"",
              categories && categories[i] ? categories[i] : "(null)");
      return FMU_ERROR;
    }
    info |= strcmp(categories[i], "logInfo") == 0;
  }
  if (info) fi->logging_on = on;
  return FMU_OK;
}

static const char *const phase_name[] = {"the instantiated state", "initialization mode",
                                         "step mode", "the terminated state",
                                         "the failed state (reset it)"};

fmu_status fmu_allowed(const fmu_instance *fi, const char *call, unsigned phases) {
  if (phases & FMU_IN(fi->clock.phase)) return FMU_OK;
  fmu_log(fi, FMU_ERROR, "%s: not allowed when the FMU is in %s", call,
          phase_name[fi->clock.phase]);
  return FMU_ERROR;
}

/* ---- instantiation and reset --------------------------------------------------------------- */

/* the parameters' values (n_params of them) into the user's params struct */
static void put_params(fmu_instance *fi, const double *value) {
  const sdae_fmu *m = fi->model;
  for (size_t i = 0; i < m->n_params; i++)
    memcpy((char *)fi->params + m->params[i].offset, &value[i], sizeof(double));
}

/* the user's mechanism at the current parameters, with the inputs */
void fmu_mechanism(fmu_instance *fi) {
  put_params(fi, fi->values + fi->layout.params);
  fi->forces.user = fi->model->mbs(fi->params);
  fi->forces.u = fi->values + fi->layout.u;
  fmu_forces_wrap(&fi->sys, &fi->forces);
}

/* the table's defaults into the user's params struct: from params_default when the table
 * gives it, else from each parameter's start */
static void fill_defaults(fmu_instance *fi) {
  const sdae_fmu *m = fi->model;
  if (m->params_default) {
    memset(fi->params, 0, m->params_size);
    m->params_default(fi->params);
    return;
  }
  for (size_t i = 0; i < m->n_params; i++)
    memcpy((char *)fi->params + m->params[i].offset, &m->params[i].start, sizeof(double));
}

/* the variables at their defaults: the table's, the solver's, the start state at the defaults */
static void defaults(fmu_instance *fi) {
  const sdae_fmu *m = fi->model;
  const fmu_layout *L = &fi->layout;
  memset(fi->values, 0, L->count * sizeof *fi->values);
  fi->values[FMU_VR_T] = m->T;
  fi->values[FMU_VR_DELTA] = m->delta;
  fi->values[FMU_VR_EPSILON] = m->epsilon;
  fill_defaults(fi);
  for (size_t i = 0; i < m->n_params; i++)
    memcpy(&fi->values[L->params + i], (const char *)fi->params + m->params[i].offset,
           sizeof(double));
  fmu_mechanism(fi);
  /* the start state at the defaults (the describer writes the same into the XML); without one
   * at the defaults it stays 0 and the importer must give q0, v0 */
  if (m->start && m->start(fi->params, fi->values + L->q0, fi->values + L->v0) != 0)
    memset(fi->values + L->q0, 0, 2 * L->n_q * sizeof *fi->values);
  fi->clock = (fmu_clock){.phase = FMU_INSTANTIATED, .map = sdae_map_by_name(m->map)};
}

/* the layout: the sizes from the mechanism at the table's defaults (they may not depend on the
 * parameters) */
static void measure(fmu_instance *fi) {
  sdae_mbs sys;
  fill_defaults(fi);
  sys = fi->model->mbs(fi->params);
  fmu_layout_make(&fi->layout, fi->model, sys.n_q, sys.n_c, sys.potential != NULL);
}

static size_t work_len(const fmu_layout *L) { return 2 * (L->n_q + L->n_c) * sizeof(double); }

void fmu_drop_stepper(fmu_instance *fi) {
  sdae_mbs_stepper_free(fi->stepper); /* its block the instance's plain bytes again */
  fi->stepper = NULL;
}

void fmu_free(fmu_instance *fi) {
  if (!fi) return;
  fmu_drop_stepper(fi);
  sdae_allocator a = fi->alloc;
  if (fi->name) fmu_mem_put(&a, fi->name, strlen(fi->name) + 1);
  fmu_mem_put(&a, fi->values, fi->layout.count * sizeof *fi->values);
  fmu_mem_put(&a, fi->params, fi->model->params_size ? fi->model->params_size : 1);
  fmu_mem_put(&a, fi->work, work_len(&fi->layout));
  fmu_mem_put(&a, fi->block, fi->block_len);
  fmu_mem_put(&a, fi, sizeof *fi);
}

const char *fmu_instance_name(const char *name) {
  return name && *name ? name : sdae_fmu_model.name;
}

fmu_instance *fmu_instantiate(const char *name, const char *token, const sdae_allocator *a,
                              fmu_logger log, void *env, int logging_on) {
  const sdae_allocator plain = {NULL, NULL, NULL};
  const sdae_fmu *m = &sdae_fmu_model;
  fmu_instance *fi = fmu_mem_get(a ? a : &plain, sizeof *fi);
  name = fmu_instance_name(name);
  if (!fi) {
    early_error(log, env, name, "instantiate: out of memory");
    return NULL;
  }
  *fi = (fmu_instance){
      .alloc = a ? *a : plain, .log = log, .env = env, .logging_on = logging_on, .model = m};
  fi->name = fmu_mem_get(&fi->alloc, strlen(name) + 1);
  fi->params = fmu_mem_get(&fi->alloc, m->params_size ? m->params_size : 1);
  if (!fi->name || !fi->params) goto nomem;
  memcpy(fi->name, name, strlen(name) + 1);
  measure(fi);
  fi->values = fmu_mem_get(&fi->alloc, fi->layout.count * sizeof *fi->values);
  fi->work = fmu_mem_get(&fi->alloc, work_len(&fi->layout));
  if (!fi->values || !fi->work) goto nomem;
  defaults(fi);
  fmu_token(&fi->layout, fi->values, fi->token);
  if (token && strcmp(token, fi->token) != 0) {
    fmu_log(fi, FMU_ERROR, "instantiate: the token %s is not this binary's %s", token, fi->token);
    fmu_free(fi);
    return NULL;
  }
  fmu_log(fi, FMU_OK, "instantiated %s (%zu coordinates, %zu constraints)", m->name, fi->layout.n_q,
          fi->layout.n_c);
  return fi;
nomem:
  early_error(log, env, name, "instantiate: out of memory");
  fmu_free(fi);
  return NULL;
}

fmu_status fmu_reset(fmu_instance *fi) {
  /* the stepper's block stays allocated (its address with it) for the next initialization */
  fmu_drop_stepper(fi);
  defaults(fi);
  return FMU_OK;
}

/* ---- initialization ------------------------------------------------------------------------ */

fmu_status fmu_enter_init(fmu_instance *fi, double t0) {
  if (fmu_allowed(fi, "enterInitializationMode", FMU_IN(FMU_INSTANTIATED)) != FMU_OK)
    return FMU_ERROR;
  if (!isfinite(t0)) {
    fmu_log(fi, FMU_ERROR, "enterInitializationMode: the start time %g is not finite", t0);
    return FMU_ERROR;
  }
  fi->clock.t = fi->clock.t_grid = t0;
  fi->clock.n_grid = 0;
  fi->clock.phase = FMU_INIT_MODE;
  return FMU_OK;
}

/* the outputs at the state (t, q, v): lambda, max |c|, the energy, all computed before any is
 * written, so that a failure leaves the outputs as they were; SDAE_OK or the library's status */
static int outputs(fmu_instance *fi, double t, const double *q, const double *v) {
  const fmu_layout *L = &fi->layout;
  double *lambda = fi->work + 2 * L->n_q, *c = lambda + L->n_c, energy = 0.0, worst = 0.0;
  double *out = fi->values;
  int rc = sdae_mbs_lambda(fi->stepper, t, q, v, lambda);
  if (rc == SDAE_OK && L->has_energy) rc = sdae_mbs_energy(fi->stepper, t, q, v, &energy);
  if (rc == SDAE_OK && fi->sys.constraint(t, q, c, fi->sys.params) != 0)
    rc = SDAE_ERR_CALLBACK_FATAL;
  if (rc != SDAE_OK) return rc;
  for (size_t j = 0; j < L->n_c; j++) worst = fmax(worst, fabs(c[j]));
  memcpy(out + L->lambda, lambda, L->n_c * sizeof *lambda);
  if (L->has_energy) out[L->energy] = energy;
  out[L->max_abs_c] = worst;
  memmove(out + L->q, q, L->n_q * sizeof *q); /* q may be the outputs themselves */
  memmove(out + L->v, v, L->n_q * sizeof *v);
  fi->outputs_stale = 0;
  return SDAE_OK;
}

/* the stepper in the instance's block, grown only when the options need more room; SDAE_OK or
 * why not */
static int build_stepper(fmu_instance *fi, const sdae_options *o) {
  size_t len = sdae_mbs_stepper_size_with(&fi->sys, o, &fi->alloc);
  unsigned char none;
  if (len == 0) { /* the mechanism or the options are invalid (the status says which), or
                   * there was no memory to analyse them in: a valid one asks for a block */
    int rc = sdae_mbs_stepper_init(&fi->stepper, &none, 0, &fi->sys, o);
    return rc == SDAE_ERR_BUFFER ? SDAE_ERR_NOMEM : rc;
  }
  if (len > fi->block_len) {
    fmu_mem_put(&fi->alloc, fi->block, fi->block_len);
    fi->block_len = 0;
    if (!(fi->block = fmu_mem_get(&fi->alloc, len))) return SDAE_ERR_NOMEM;
    fi->block_len = len;
  }
  return sdae_mbs_stepper_init(&fi->stepper, fi->block, fi->block_len, &fi->sys, o);
}

fmu_status fmu_build(fmu_instance *fi, const char *call) {
  const fmu_layout *L = &fi->layout;
  sdae_options o;
  int rc;
  fmu_mechanism(fi);
  sdae_options_default(&o);
  o.scheme = SDAE_SCHEME_SEMI_IMPLICIT;
  o.delta = fi->values[FMU_VR_DELTA];
  o.epsilon = fi->values[FMU_VR_EPSILON];
  o.map = fi->clock.map;
  fmu_drop_stepper(fi);
  if ((rc = build_stepper(fi, &o)) != SDAE_OK) {
    fmu_drop_stepper(fi);
    fmu_log(fi, FMU_ERROR,
            "%s: the mechanism or the solver's settings (map %s, delta %g, epsilon %g): %s", call,
            sdae_map_name(o.map), o.delta, o.epsilon, sdae_strerror(rc));
    return FMU_ERROR;
  }
  if ((rc = outputs(fi, fi->clock.t, fi->values + L->q, fi->values + L->v)) != SDAE_OK) {
    fmu_drop_stepper(fi);
    fmu_log(fi, FMU_ERROR, "%s: the outputs at the state: %s", call, sdae_strerror(rc));
    return FMU_ERROR;
  }
  return FMU_OK;
}

/* the start state (start at the parameters unless the importer set q0 or v0), the stepper and
 * the outputs there: exitInitializationMode, and a get of an output in initialization mode */
static fmu_status initial_state(fmu_instance *fi, const char *call) {
  const fmu_layout *L = &fi->layout;
  double *q0 = fi->values + L->q0, *v0 = fi->values + L->v0;
  fmu_mechanism(fi);
  if (!fi->clock.start_set && fi->model->start && fi->model->start(fi->params, q0, v0) != 0) {
    fmu_log(fi, FMU_ERROR,
            "%s: the mechanism has no start state at these parameters; set q0 and v0", call);
    return FMU_ERROR;
  }
  for (size_t i = 0; i < 2 * L->n_q; i++)
    if (!isfinite(q0[i])) { /* q0 and v0 are adjacent */
      fmu_log(fi, FMU_ERROR, "%s: the start state is not finite (%s[%zu] = %g)", call,
              i < L->n_q ? "q0" : "v0", i % L->n_q + 1, q0[i]);
      return FMU_ERROR;
    }
  memcpy(fi->values + L->q, q0, L->n_q * sizeof *q0);
  memcpy(fi->values + L->v, v0, L->n_q * sizeof *v0);
  return fmu_build(fi, call);
}

fmu_status fmu_exit_init(fmu_instance *fi) {
  if (fmu_allowed(fi, "exitInitializationMode", FMU_IN(FMU_INIT_MODE)) != FMU_OK) return FMU_ERROR;
  /* a new stepper even after a get in initialization mode: the run starts from its fresh state */
  if (initial_state(fi, "exitInitializationMode") != FMU_OK) return FMU_ERROR;
  fi->clock.phase = FMU_STEP_MODE;
  return FMU_OK;
}

/* ---- doStep -------------------------------------------------------------------------------- */

/* Steps of T from the grid t_grid + i T when h is a multiple of T, so that k T reproduces a
 * fixed-step run exactly; otherwise k equal steps of h / k (k = ceil(h / T)), all ending at
 * t + h, the grid starting anew there. */
static int substeps(fmu_instance *fi, double h, unsigned long long k, double *q, double *v) {
  fmu_clock *c = &fi->clock;
  double T = fi->values[FMU_VR_T], t = c->t;
  int rc = SDAE_OK;
  if (fabs(h - (double)k * T) <= 1e-9 * T) {
    for (unsigned long long i = 0; i < k && rc == SDAE_OK; i++) {
      rc = sdae_mbs_step(fi->stepper, c->t_grid + (double)c->n_grid * T, T, q, v);
      if (rc == SDAE_OK) c->n_grid++;
    }
  } else {
    double Th = h / (double)k;
    for (unsigned long long i = 0; i < k && rc == SDAE_OK; i++)
      rc = sdae_mbs_step(fi->stepper, t + (double)i * Th, Th, q, v);
    c->t_grid = t + h;
    c->n_grid = 0;
  }
  /* the FMU's time is the grid's origin and a count of steps, never a running sum of the
   * importer's steps: it does not drift from t0 + n T, whatever t0 */
  c->t = c->t_grid + (double)c->n_grid * T;
  return rc;
}

/* The importer's communication point is the FMU's time up to rounding: within T / 1000, an
 * absolute bound in units of the step (a relative one admits whole steps off at a large t0),
 * or two ulps of a time so large that T / 1000 is below its resolution. */
static int at_own_time(const fmu_instance *fi, double t) {
  double own = fi->clock.t;
  return fabs(t - own) <= fmax(1e-3 * fi->values[FMU_VR_T], 4.0 * DBL_EPSILON * fabs(own));
}

/* k = ceil(h / T) steps (a hair below a multiple of T counts as it, as the programs' rule
 * ceil(tf/T - 1e-9)); 0 when there would be more than 2^53 (h / T not a count of steps) */
static unsigned long long steps_in(double h, double T) {
  double k = ceil(h / T - 1e-9);
  if (!(k <= 9007199254740992.0)) return 0;
  return k < 1.0 ? 1 : (unsigned long long)k;
}

fmu_status fmu_do_step(fmu_instance *fi, double t, double h) {
  const fmu_layout *L = &fi->layout;
  double *q = fi->work, *v = fi->work + L->n_q;
  fmu_clock before = fi->clock;
  unsigned long long k;
  int rc;
  if (fmu_allowed(fi, "doStep", FMU_IN(FMU_STEP_MODE)) != FMU_OK) return FMU_ERROR;
  if (!(isfinite(h) && h > 0.0)) {
    fmu_log(fi, FMU_ERROR, "doStep: the communication step %g is not positive and finite", h);
    return FMU_ERROR;
  }
  if (!at_own_time(fi, t)) {
    fmu_log(fi, FMU_ERROR,
            "doStep: the communication point %.17g is not the FMU's time %.17g (to T/1000)", t,
            fi->clock.t);
    return FMU_ERROR;
  }
  if (!(k = steps_in(h, fi->values[FMU_VR_T]))) {
    fmu_log(fi, FMU_ERROR, "doStep: the communication step %g is more than 2^53 steps of T = %g", h,
            fi->values[FMU_VR_T]);
    return FMU_ERROR;
  }
  memcpy(q, fi->values + L->q, L->n_q * sizeof *q);
  memcpy(v, fi->values + L->v, L->n_q * sizeof *v);
  rc = substeps(fi, h, k, q, v);
  if (rc == SDAE_OK) rc = outputs(fi, fi->clock.t, q, v);
  if (rc != SDAE_OK) {
    /* the outputs stay those of t; nothing more until reset */
    fi->clock = before;
    fi->clock.phase = FMU_FAILED;
    fmu_log(fi, FMU_ERROR,
            "doStep: a step between %.17g and %.17g failed: %s (the outputs are those at %.17g; "
            "reset the FMU)",
            t, t + h, sdae_strerror(rc), before.t);
    return FMU_ERROR;
  }
  return FMU_OK;
}

fmu_status fmu_terminate(fmu_instance *fi) {
  if (fmu_allowed(fi, "terminate", FMU_IN(FMU_STEP_MODE) | FMU_IN(FMU_FAILED)) != FMU_OK)
    return FMU_ERROR;
  fi->clock.phase = FMU_TERMINATED;
  return FMU_OK;
}

/* ---- variables ----------------------------------------------------------------------------- */

/* the variable vr, or FMU_ERROR with a message */
static fmu_status lookup(const fmu_instance *fi, const char *call, unsigned vr, int string,
                         fmu_var *var) {
  if (fmu_var_at(&fi->layout, vr, var) != 0) {
    fmu_log(fi, FMU_ERROR, "%s: no variable has the value reference %u", call, vr);
    return FMU_ERROR;
  }
  if (var->is_string != string) {
    fmu_log(fi, FMU_ERROR, "%s: %s (value reference %u) is a %s", call, var->name, vr,
            var->is_string ? "string" : "Float64/Real");
    return FMU_ERROR;
  }
  return FMU_OK;
}

/* the outputs at the current inputs, when one was set since they were computed (the Reference
 * FMUs' way: outputs computed on the get that needs them). Not in the failed state, whose
 * outputs stay those of the last good communication point. */
static fmu_status fresh_outputs(fmu_instance *fi) {
  const fmu_layout *L = &fi->layout;
  int rc;
  if (!fi->outputs_stale || !fi->stepper || fi->clock.phase == FMU_FAILED) return FMU_OK;
  if ((rc = outputs(fi, fi->clock.t, fi->values + L->q, fi->values + L->v)) == SDAE_OK)
    return FMU_OK;
  fmu_log(fi, FMU_ERROR, "getReal: the outputs at the inputs set: %s", sdae_strerror(rc));
  return FMU_ERROR;
}

fmu_status fmu_get_real(fmu_instance *fi, const unsigned *vr, size_t n, double *value) {
  fmu_var var;
  if (n > 0 && (!vr || !value)) {
    fmu_log(fi, FMU_ERROR, "getReal: NULL arrays");
    return FMU_ERROR;
  }
  for (size_t i = 0; i < n; i++) {
    if (lookup(fi, "getReal", vr[i], 0, &var) != FMU_OK) return FMU_ERROR;
    if (var.role == FMU_OUTPUT && !fi->stepper && fi->clock.phase == FMU_INIT_MODE &&
        initial_state(fi, "getReal") != FMU_OK)
      return FMU_ERROR;
    if (var.role == FMU_OUTPUT && !fi->stepper) {
      fmu_log(fi, FMU_ERROR, "getReal: %s is computed from initialization mode on", var.name);
      return FMU_ERROR;
    }
    if (var.role == FMU_OUTPUT && fresh_outputs(fi) != FMU_OK) return FMU_ERROR;
    value[i] = var.role == FMU_TIME ? fi->clock.t : fi->values[vr[i]];
  }
  return FMU_OK;
}

/* a value for var, or FMU_ERROR with a message: bad input never reaches the stepper */
static fmu_status check_value(const fmu_instance *fi, const fmu_var *var, double x) {
  const char *why = NULL;
  unsigned before_init = FMU_IN(FMU_INSTANTIATED) | FMU_IN(FMU_INIT_MODE);
  if (var->role == FMU_TIME || var->role == FMU_OUTPUT)
    why = "is not a parameter or an input";
  else if (var->role == FMU_INPUT)
    why = isfinite(x) ? NULL : "must be finite";
  else if (!(FMU_IN(fi->clock.phase) & before_init))
    why = "is a fixed parameter, set before exitInitializationMode only";
  else if (!isfinite(x))
    why = "must be finite";
  else if (var->role == FMU_SOLVER && !(x > 0.0))
    why = "must be positive";
  if (!why && var->role == FMU_INPUT &&
      !(FMU_IN(fi->clock.phase) & (before_init | FMU_IN(FMU_STEP_MODE))))
    why = "is set before initialization or in step mode only";
  if (!why) return FMU_OK;
  fmu_log(fi, FMU_ERROR, "setReal: %s = %g: %s %s", var->name, x, var->name, why);
  return FMU_ERROR;
}

fmu_status fmu_set_real(fmu_instance *fi, const unsigned *vr, size_t n, const double *value) {
  fmu_var var;
  if (n > 0 && (!vr || !value)) {
    fmu_log(fi, FMU_ERROR, "setReal: NULL arrays");
    return FMU_ERROR;
  }
  /* all checked before any is set: a refused call changes nothing */
  for (size_t i = 0; i < n; i++)
    if (lookup(fi, "setReal", vr[i], 0, &var) != FMU_OK ||
        check_value(fi, &var, value[i]) != FMU_OK)
      return FMU_ERROR;
  for (size_t i = 0; i < n; i++) {
    fmu_var_at(&fi->layout, vr[i], &var);
    /* a start value set to the one it holds (an importer writing back every start value of
     * the XML) leaves the start to the mechanism's parameters */
    if (var.role == FMU_START && value[i] != fi->values[vr[i]]) fi->clock.start_set = 1;
    if (var.role == FMU_INPUT) fi->outputs_stale = 1;
    fi->values[vr[i]] = value[i];
  }
  /* outputs got in initialization mode came from the values before: computed anew when asked */
  if (fi->clock.phase == FMU_INIT_MODE) fmu_drop_stepper(fi);
  return FMU_OK;
}

fmu_status fmu_get_string(fmu_instance *fi, const unsigned *vr, size_t n, const char **value) {
  fmu_var var;
  if (n > 0 && (!vr || !value)) {
    fmu_log(fi, FMU_ERROR, "getString: NULL arrays");
    return FMU_ERROR;
  }
  for (size_t i = 0; i < n; i++) {
    if (lookup(fi, "getString", vr[i], 1, &var) != FMU_OK) return FMU_ERROR;
    value[i] = sdae_map_name(fi->clock.map);
  }
  return FMU_OK;
}

fmu_status fmu_set_string(fmu_instance *fi, const unsigned *vr, size_t n,
                          const char *const *value) {
  fmu_var var;
  if (n > 0 && (!vr || !value)) {
    fmu_log(fi, FMU_ERROR, "setString: NULL arrays");
    return FMU_ERROR;
  }
  for (size_t i = 0; i < n; i++) {
    const sdae_map_type *map = value[i] ? sdae_map_by_name(value[i]) : NULL;
    if (lookup(fi, "setString", vr[i], 1, &var) != FMU_OK ||
        fmu_allowed(fi, "setString map", FMU_IN(FMU_INSTANTIATED) | FMU_IN(FMU_INIT_MODE)) !=
            FMU_OK)
      return FMU_ERROR;
    /* the user map needs a callback the mechanism cannot give through the table */
    if (!map || map == sdae_map_user) {
      fmu_log(fi, FMU_ERROR,
              "setString: map = \"%s\": no such map (euler, midpoint, dgrad, dg4, dg6, "
              "midpoint4, midpoint6, rk4, rk8)",
              value[i] ? value[i] : "(null)");
      return FMU_ERROR;
    }
  }
  for (size_t i = 0; i < n; i++) fi->clock.map = sdae_map_by_name(value[i]);
  if (fi->clock.phase == FMU_INIT_MODE) fmu_drop_stepper(fi); /* as in fmu_set_real */
  return FMU_OK;
}
