/* SPDX-License-Identifier: GPL-3.0-or-later */
/* FMI 2.0 co-simulation over the co-simulation layer (fmu_instance.h, fmu_state.h): each
 * function checks its instance, maps its arguments and answers the layer's status as an
 * fmi2Status. Every allocation, the instance's and the FMU states', goes through the importer's
 * allocateMemory and freeMemory, handed to the layer as an sdae_allocator. */
#include <string.h>

#include "fmi2_glue.h"
#include "fmu_instance.h"
#include "fmu_state.h"

/* the importer's callbacks, an allocator over them, the start time of setupExperiment */
typedef struct fmi2_handle {
  fmi2CallbackFunctions cb;
  sdae_allocator alloc;
  // cppcheck-suppress unusedStructMember ; read through the macro H below, which cppcheck misses
  double t_start;
  fmu_instance *fi;
} fmi2_handle;

#define H(c) ((fmi2_handle *)(c))
#define FI(c) (H(c)->fi)

static void *alloc2(void *ud, size_t size) {
  const fmi2_handle *h = ud;
  return h->cb.allocateMemory(1, size);
}

static void free2(void *ud, void *ptr, size_t size) {
  const fmi2_handle *h = ud;
  (void)size;
  h->cb.freeMemory(ptr);
}

static void log_fmi2(void *env, const char *instance, fmu_status status, const char *category,
                     const char *message) {
  const fmi2_handle *h = env;
  if (h->cb.logger)
    h->cb.logger(h->cb.componentEnvironment, instance, (fmi2Status)status, category, message);
}

fmi2Status fmi2_unsupported(fmi2Component c, const char *function) {
  if (c) fmu_log(FI(c), FMU_ERROR, "%s: not offered by this FMU", function);
  return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_set_logging(FI(c), loggingOn, nCategories, categories);
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
  fmi2_handle *h;
  (void)fmuResourceLocation, (void)visible;
  if (!functions || !functions->allocateMemory || !functions->freeMemory) return NULL;
  if (!(h = functions->allocateMemory(1, sizeof *h))) return NULL;
  memset(h, 0, sizeof *h);
  h->cb = *functions;
  h->alloc = (sdae_allocator){alloc2, free2, h};
  if (fmuType != fmi2CoSimulation) {
    log_fmi2(h, fmu_instance_name(instanceName), FMU_ERROR, "logStatusError",
             "instantiate: this FMU offers co-simulation only");
    functions->freeMemory(h);
    return NULL;
  }
  h->fi = fmu_instantiate(instanceName, fmuGUID, &h->alloc, log_fmi2, h, loggingOn);
  if (!h->fi) {
    functions->freeMemory(h);
    return NULL;
  }
  return h;
}

void fmi2FreeInstance(fmi2Component c) {
  fmi2CallbackFreeMemory release;
  if (!c) return;
  release = H(c)->cb.freeMemory;
  fmu_free(FI(c));
  release(c);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
  if (!c) return fmi2Error;
  if (fmu_allowed(FI(c), "setupExperiment", FMU_IN(FMU_INSTANTIATED)) != FMU_OK) return fmi2Error;
  H(c)->t_start = startTime;
  return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_enter_init(FI(c), H(c)->t_start);
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_exit_init(FI(c));
}

fmi2Status fmi2Terminate(fmi2Component c) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_terminate(FI(c));
}

fmi2Status fmi2Reset(fmi2Component c) {
  if (!c) return fmi2Error;
  H(c)->t_start = 0.0;
  return (fmi2Status)fmu_reset(FI(c));
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_get_real(FI(c), vr, nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_set_real(FI(c), vr, nvr, value);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_get_string(FI(c), vr, nvr, value);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_set_string(FI(c), vr, nvr, value);
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  (void)noSetFMUStatePriorToCurrentPoint;
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_do_step(FI(c), currentCommunicationPoint, communicationStepSize);
}

/* ---- the FMU state ------------------------------------------------------------------------- */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
  if (!c || !FMUstate) return fmi2Error;
  return (fmi2Status)fmu_state_get(FI(c), (fmu_state **)FMUstate);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_state_set(FI(c), FMUstate);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
  if (!c) return fmi2Error;
  if (FMUstate) {
    fmu_state_free(FI(c), *FMUstate);
    *FMUstate = NULL;
  }
  return fmi2OK;
}

// cppcheck-suppress constParameter ; the standard's prototype (fmi2Functions.h)
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
  if (!c || !size) return fmi2Error;
  *size = fmu_state_size(FMUstate);
  return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                 size_t size) {
  if (!c) return fmi2Error;
  return (fmi2Status)fmu_state_serialize(FI(c), FMUstate, (unsigned char *)serializedState, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate) {
  if (!c || !FMUstate) return fmi2Error;
  return (fmi2Status)fmu_state_deserialize(FI(c), (const unsigned char *)serializedState, size,
                                           (fmu_state **)FMUstate);
}
