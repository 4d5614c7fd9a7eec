/*
 * The FMI 2.0 Co-Simulation state machine of the towcable FMUs: which call is allowed
 * in which state, which variable may be set in which state, and the state a call
 * leaves. fmu_loader.c applies these rules to every call before pythonfmu sees it.
 */
#ifndef TOWCABLE_STATE_MACHINE_H
#define TOWCABLE_STATE_MACHINE_H

#include <stddef.h>

#include "fmi2Functions.h"
#include "model_table.h"

typedef enum {
    PHASE_INSTANTIATED,
    PHASE_INITIALIZATION, /* initialization mode */
    PHASE_STEP,           /* slave initialized: step complete (a refused step leaves it here) */
    PHASE_TERMINATED,
    PHASE_ERROR,          /* a call that may have changed the instance failed */
    PHASE_BROKEN,         /* pythonfmu returned fmi2Fatal: its Python objects are released */
    PHASE_COUNT
} Phase;

typedef enum {
    CALL_SET_DEBUG_LOGGING, CALL_SETUP_EXPERIMENT, CALL_ENTER_INITIALIZATION, CALL_EXIT_INITIALIZATION,
    CALL_TERMINATE, CALL_RESET, CALL_GET, CALL_SET, CALL_GET_STATE, CALL_SET_STATE, CALL_FREE_STATE,
    CALL_SERIALIZE, CALL_DESERIALIZE, CALL_DO_STEP, CALL_STATUS, CALL_UNPROVIDED, CALL_COUNT
} Call;

const char *phase_name(Phase phase);

/* Whether the call may be made in the phase (FMI 2.0.4, table of section 4.2.4). */
int call_allowed(Call call, Phase phase);

/* Whether variable v may be set in the phase; if not, why (for the message). */
int set_allowed(const Variable *v, Phase phase, char *why, size_t n);

/* The phase after a call that returned status (set and get calls leave it unchanged;
   fmi2SetFMUstate takes the phase of the state and is not covered here). */
Phase phase_after(Call call, Phase before, fmi2Status status);

#endif
