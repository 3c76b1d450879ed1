/* SPDX-License-Identifier: GPL-3.0-or-later */
/* The functions of FMI 2.0 that a co-simulation FMU of a mechanism does not offer (model
 * exchange, directional derivatives, Integer and Boolean variables, asynchronous steps and
 * their status): each answers fmi2Error with a message. They exist so that an importer which
 * looks every function up finds them. One macro per family of signatures, as in
 * fmi3_unsupported.c; the parameters are there for fmi2Functions.h's prototypes alone. */
#include "fmi2_glue.h"

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic ignored "-Wunused-parameter"
#endif
/* NOLINTBEGIN(misc-unused-parameters): the prototypes' parameters, unused by design */

/* name(c, ...) answering fmi2Error with its own name */
#define UNSUPPORTED(name, ...)                                                                     \
  fmi2Status name(fmi2Component c, __VA_ARGS__) { return fmi2_unsupported(c, #name); }
#define UNSUPPORTED_0(name)                                                                        \
  fmi2Status name(fmi2Component c) { return fmi2_unsupported(c, #name); }
#define VR const fmi2ValueReference vr[], size_t nvr
/* fmi2GetT and fmi2SetT of a type T */
#define GET_SET(T)                                                                                 \
  UNSUPPORTED(fmi2Get##T, VR, fmi2##T value[])                                                     \
  UNSUPPORTED(fmi2Set##T, VR, const fmi2##T value[])

GET_SET(Integer)
GET_SET(Boolean)
UNSUPPORTED(fmi2GetDirectionalDerivative, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
            const fmi2ValueReference vKnown_ref[], size_t nKnown, const fmi2Real dvKnown[],
            fmi2Real dvUnknown[])
UNSUPPORTED(fmi2SetRealInputDerivatives, VR, const fmi2Integer order[], const fmi2Real value[])
UNSUPPORTED(fmi2GetRealOutputDerivatives, VR, const fmi2Integer order[], fmi2Real value[])

UNSUPPORTED_0(fmi2EnterEventMode)
UNSUPPORTED(fmi2NewDiscreteStates, fmi2EventInfo *fmi2eventInfo)
UNSUPPORTED_0(fmi2EnterContinuousTimeMode)
UNSUPPORTED(fmi2CompletedIntegratorStep, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
            fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
UNSUPPORTED(fmi2SetTime, fmi2Real time)
UNSUPPORTED(fmi2SetContinuousStates, const fmi2Real x[], size_t nx)
UNSUPPORTED(fmi2GetDerivatives, fmi2Real derivatives[], size_t nx)
UNSUPPORTED(fmi2GetEventIndicators, fmi2Real eventIndicators[], size_t ni)
UNSUPPORTED(fmi2GetContinuousStates, fmi2Real x[], size_t nx)
UNSUPPORTED(fmi2GetNominalsOfContinuousStates, fmi2Real x_nominal[], size_t nx)

UNSUPPORTED_0(fmi2CancelStep)
UNSUPPORTED(fmi2GetStatus, const fmi2StatusKind s, fmi2Status *value)
UNSUPPORTED(fmi2GetRealStatus, const fmi2StatusKind s, fmi2Real *value)
UNSUPPORTED(fmi2GetIntegerStatus, const fmi2StatusKind s, fmi2Integer *value)
UNSUPPORTED(fmi2GetBooleanStatus, const fmi2StatusKind s, fmi2Boolean *value)
UNSUPPORTED(fmi2GetStringStatus, const fmi2StatusKind s, fmi2String *value)
/* NOLINTEND(misc-unused-parameters) */
