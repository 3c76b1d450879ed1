/* SPDX-License-Identifier: GPL-3.0-or-later */
/* FMI 3.0 co-simulation over the co-simulation layer (fmu_instance.h, fmu_state.h): each
 * function checks its instance, maps its arguments and answers the layer's status as an
 * fmi3Status. Variables are Float64 scalars but map, a String. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_glue.h"
#include "fmu_instance.h"
#include "fmu_state.h"

/* the importer's logMessage behind the layer's logger */
typedef struct fmi3_env {
  fmi3InstanceEnvironment env;
  fmi3LogMessageCallback log;
} fmi3_env;

/* FMI 3.0's logMessage has no argument for the instance's name: the message begins with it */
static void log_fmi3(void *env, const char *instance, fmu_status status, const char *category,
                     const char *message) {
  const fmi3_env *e = env;
  char named[640];
  snprintf(named, sizeof named, "%s: %s", instance, message);
  if (e->log) e->log(e->env, (fmi3Status)status, category, named);
}

/* each instance keeps its environment beside it: one allocation, freed with it */
typedef struct fmi3_handle {
  fmi3_env env;
  fmu_instance *fi;
} fmi3_handle;

#define FI(instance) (((fmi3_handle *)(instance))->fi)

fmi3Status fmi3_unsupported(fmi3Instance instance, const char *function) {
  if (instance) fmu_log(FI(instance), FMU_ERROR, "%s: not offered by this FMU", function);
  return fmi3Error;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_set_logging(FI(instance), loggingOn, nCategories, categories);
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
  fmi3_env e = {instanceEnvironment, logMessage};
  fmi3_handle *h;
  (void)resourcePath, (void)visible, (void)earlyReturnAllowed, (void)intermediateUpdate;
  (void)requiredIntermediateVariables;
  if (eventModeUsed || nRequiredIntermediateVariables > 0) {
    log_fmi3(&e, fmu_instance_name(instanceName), FMU_ERROR, "logStatusError",
             "instantiate: event mode and intermediate variables are not offered");
    return NULL;
  }
  if (!(h = malloc(sizeof *h))) {
    log_fmi3(&e, fmu_instance_name(instanceName), FMU_ERROR, "logStatusError",
             "instantiate: out of memory");
    return NULL;
  }
  h->env = e;
  h->fi = fmu_instantiate(instanceName, instantiationToken, NULL, log_fmi3, &h->env, loggingOn);
  if (!h->fi) {
    free(h);
    return NULL;
  }
  return h;
}

void fmi3FreeInstance(fmi3Instance instance) {
  if (!instance) return;
  fmu_free(FI(instance));
  free(instance);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
  (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_enter_init(FI(instance), startTime);
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_exit_init(FI(instance));
}

/* co-simulation without event mode: the FMU is in step mode after initialization */
fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_allowed(FI(instance), "enterStepMode", FMU_IN(FMU_STEP_MODE));
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_terminate(FI(instance));
}

fmi3Status fmi3Reset(fmi3Instance instance) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_reset(FI(instance));
}

/* nValues is nValueReferences: every variable is a scalar */
static fmi3Status scalars(fmi3Instance instance, const char *call, size_t nvr, size_t nValues) {
  if (!instance) return fmi3Error;
  if (nValues == nvr) return fmi3OK;
  fmu_log(FI(instance), FMU_ERROR, "%s: %zu values for %zu scalar variables", call, nValues, nvr);
  return fmi3Error;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues) {
  if (scalars(instance, "getFloat64", nValueReferences, nValues) != fmi3OK) return fmi3Error;
  return (fmi3Status)fmu_get_real(FI(instance), valueReferences, nValueReferences, values);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues) {
  if (scalars(instance, "setFloat64", nValueReferences, nValues) != fmi3OK) return fmi3Error;
  return (fmi3Status)fmu_set_real(FI(instance), valueReferences, nValueReferences, values);
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, fmi3String values[], size_t nValues) {
  if (scalars(instance, "getString", nValueReferences, nValues) != fmi3OK) return fmi3Error;
  return (fmi3Status)fmu_get_string(FI(instance), valueReferences, nValueReferences, values);
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const fmi3String values[], size_t nValues) {
  if (scalars(instance, "setString", nValueReferences, nValues) != fmi3OK) return fmi3Error;
  return (fmi3Status)fmu_set_string(FI(instance), valueReferences, nValueReferences, values);
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
  fmu_status rc;
  (void)noSetFMUStatePriorToCurrentPoint;
  if (!instance) return fmi3Error;
  rc = fmu_do_step(FI(instance), currentCommunicationPoint, communicationStepSize);
  if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
  if (terminateSimulation) *terminateSimulation = fmi3False;
  if (earlyReturn) *earlyReturn = fmi3False;
  if (lastSuccessfulTime) *lastSuccessfulTime = FI(instance)->clock.t;
  return (fmi3Status)rc;
}

/* ---- the FMU state ------------------------------------------------------------------------- */

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
  if (!instance || !FMUState) return fmi3Error;
  return (fmi3Status)fmu_state_get(FI(instance), (fmu_state **)FMUState);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_state_set(FI(instance), FMUState);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
  if (!instance) return fmi3Error;
  if (FMUState) {
    fmu_state_free(FI(instance), *FMUState);
    *FMUState = NULL;
  }
  return fmi3OK;
}

// cppcheck-suppress constParameter ; the standard's prototype (fmi3Functions.h)
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size) {
  if (!instance || !size) return fmi3Error;
  *size = fmu_state_size(FMUState);
  return fmi3OK;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                 fmi3Byte serializedState[], size_t size) {
  if (!instance) return fmi3Error;
  return (fmi3Status)fmu_state_serialize(FI(instance), FMUState, serializedState, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState *FMUState) {
  if (!instance || !FMUState) return fmi3Error;
  return (fmi3Status)fmu_state_deserialize(FI(instance), serializedState, size,
                                           (fmu_state **)FMUState);
}
