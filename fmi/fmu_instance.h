/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The co-simulation layer under both FMI versions (fmi3_functions.c, fmi2_functions.c): one
 * instance of the table's mechanism (<stabdae/fmu.h>), its variables by value reference, the
 * state machine, doStep over sdae_mbs_step, and the messages through the importer's logger.
 * It speaks no FMI type: each version's file maps its calls and statuses onto these. Every
 * allocation goes through the instance's sdae_allocator (FMI 2.0's memory callbacks). */
#ifndef STABDAE_FMI_FMU_INSTANCE_H
#define STABDAE_FMI_FMU_INSTANCE_H

#include <stddef.h>

#include <stabdae/fmu.h>

#include "fmu_forces.h"
#include "fmu_vars.h"

typedef enum fmu_status { FMU_OK, FMU_WARNING, FMU_DISCARD, FMU_ERROR, FMU_FATAL } fmu_status;

/* the state machine, common to FMI 3.0 and 2.0 co-simulation */
typedef enum fmu_phase {
  FMU_INSTANTIATED, /* parameters, start state and inputs may be set */
  FMU_INIT_MODE,    /* the same; exitInitializationMode builds the stepper */
  FMU_STEP_MODE,    /* doStep, inputs, get and set of the FMU state */
  FMU_TERMINATED,   /* outputs may be read; reset or free */
  FMU_FAILED        /* a step failed: outputs of the last good point; reset or free */
} fmu_phase;

/* instance: the instance's name, on every message; category: "logStatusError",
 * "logStatusWarning" or "logInfo" */
typedef void (*fmu_logger)(void *env, const char *instance, fmu_status status, const char *category,
                           const char *message);

/* What a snapshot of the FMU state copies, apart from the variables and the stepper's block. */
typedef struct fmu_clock {
  fmu_phase phase;
  double t;                  /* the communication point reached */
  double t_grid;             /* the origin of the internal steps of T */
  unsigned long long n_grid; /* steps of T taken from t_grid: step i starts at t_grid + i T */
  int start_set;             /* the importer set q0 or v0 */
  const sdae_map_type *map;
} fmu_clock;

typedef struct fmu_instance {
  sdae_allocator alloc;
  fmu_logger log;
  void *env;
  int logging_on;
  char *name;
  const sdae_fmu *model;
  fmu_layout layout;
  char token[40]; /* the instantiation token / guid, from the defaults (fmu_token) */
  fmu_clock clock;
  double *values;    /* layout.count doubles by value reference (map's entry unused) */
  void *params;      /* the user's params struct, model->params_size bytes */
  fmu_forces forces; /* the user's mechanism with the inputs u */
  sdae_mbs sys;      /* what the stepper integrates: forces wrapped */
  void *block;       /* the stepper's block, kept from one initialization to the next */
  size_t block_len;
  sdae_mbs_stepper *stepper; /* in block; NULL before exitInitializationMode */
  double *work;              /* 2 n_q + 2 n_c: a communication step's q, v; lambda, c */
  /* an input was set, or an FMU state put back, since the outputs were computed: lambda
   * depends on u directly, so the next get computes the outputs again */
  int outputs_stale;
} fmu_instance;

/* size bytes, zeroed, from the allocator a (malloc without one); NULL when there is no room */
void *fmu_mem_get(const sdae_allocator *a, size_t size);
void fmu_mem_put(const sdae_allocator *a, void *p, size_t size); /* p NULL is fine */

/* the instance's name: the importer's, or the model's when the importer gives none */
const char *fmu_instance_name(const char *name);

/* NULL (after a message through log) when the token is not this binary's or memory fails. */
fmu_instance *fmu_instantiate(const char *name, const char *token, const sdae_allocator *a,
                              fmu_logger log, void *env, int logging_on);
void fmu_free(fmu_instance *fi); /* NULL is fine */
/* the instance's stepper given up (sdae_mbs_stepper_free: its block, kept for the next one,
 * plain bytes again), fi->stepper NULL */
void fmu_drop_stepper(fmu_instance *fi);

/* the message, through the logger: errors and warnings always, information when logging is on */
void fmu_log(const fmu_instance *fi, fmu_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* the user's mechanism at the current parameters, with the inputs, in fi->sys */
void fmu_mechanism(fmu_instance *fi);
/* the stepper at the current variables and the outputs at the state (q, v) the variables hold;
 * FMU_ERROR with a message naming call */
fmu_status fmu_build(fmu_instance *fi, const char *call);

/* logging on or off; the categories named must be the FMU's (none named: all of them) */
fmu_status fmu_set_logging(fmu_instance *fi, int on, size_t n, const char *const *categories);

fmu_status fmu_enter_init(fmu_instance *fi, double t0);
fmu_status fmu_exit_init(fmu_instance *fi);
fmu_status fmu_do_step(fmu_instance *fi, double t, double h);
fmu_status fmu_terminate(fmu_instance *fi);
fmu_status fmu_reset(fmu_instance *fi);

/* the calls' states: FMU_ERROR with a message naming the call when fi is not in one of them */
fmu_status fmu_allowed(const fmu_instance *fi, const char *call, unsigned phases);
#define FMU_IN(phase) (1u << (phase))

fmu_status fmu_get_real(fmu_instance *fi, const unsigned *vr, size_t n, double *value);
fmu_status fmu_set_real(fmu_instance *fi, const unsigned *vr, size_t n, const double *value);
fmu_status fmu_get_string(fmu_instance *fi, const unsigned *vr, size_t n, const char **value);
fmu_status fmu_set_string(fmu_instance *fi, const unsigned *vr, size_t n, const char *const *value);

#endif /* STABDAE_FMI_FMU_INSTANCE_H */
