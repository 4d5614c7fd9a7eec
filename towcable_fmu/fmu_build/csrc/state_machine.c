/*
 * The rules of state_machine.h. Departures from the letter of FMI 2.0, both on the
 * permissive side:
 *
 * - a call this layer or the model refuses before it changed anything (a call not
 *   allowed in the state, a variable that may not be set, an unknown value reference,
 *   bytes that are not a state of this FMU, a parameter out of range) returns fmi2Error
 *   and leaves the state as it was; only a call that failed after it may have changed
 *   the instance (fmi2EnterInitializationMode, fmi2ExitInitializationMode, fmi2DoStep,
 *   fmi2Terminate, fmi2Reset) leaves it in the error state, where fmi2Get* (for
 *   diagnosis), the FMU-state calls (restore a state saved before), fmi2Reset and
 *   fmi2FreeInstance are allowed;
 * - fmi2DoStep returns fmi2Discard only for a step the model refused and undid (design
 *   rule 5: the model stays at the communication point), so the slave stays in step
 *   mode and may step again (a standard master restores a state first, which also works).
 *
 * Inputs may be set in the instantiated state too (they have start values).
 */
#include "state_machine.h"

#include <stdio.h>
#include <string.h>

#define IN(phase) (1u << (phase))
#define LIVE (IN(PHASE_INSTANTIATED) | IN(PHASE_INITIALIZATION) | IN(PHASE_STEP) | IN(PHASE_TERMINATED) \
              | IN(PHASE_ERROR))

static const unsigned ALLOWED[CALL_COUNT] = {
    [CALL_SET_DEBUG_LOGGING] = LIVE,
    [CALL_SETUP_EXPERIMENT] = IN(PHASE_INSTANTIATED),
    [CALL_ENTER_INITIALIZATION] = IN(PHASE_INSTANTIATED),
    [CALL_EXIT_INITIALIZATION] = IN(PHASE_INITIALIZATION),
    [CALL_TERMINATE] = IN(PHASE_STEP),
    [CALL_RESET] = LIVE,
    [CALL_GET] = IN(PHASE_INITIALIZATION) | IN(PHASE_STEP) | IN(PHASE_TERMINATED) | IN(PHASE_ERROR),
    [CALL_SET] = IN(PHASE_INSTANTIATED) | IN(PHASE_INITIALIZATION) | IN(PHASE_STEP),
    [CALL_GET_STATE] = LIVE,
    [CALL_SET_STATE] = LIVE,
    [CALL_FREE_STATE] = LIVE,
    [CALL_SERIALIZE] = LIVE,
    [CALL_DESERIALIZE] = LIVE,
    [CALL_DO_STEP] = IN(PHASE_STEP),
    [CALL_STATUS] = IN(PHASE_STEP) | IN(PHASE_TERMINATED),
    [CALL_UNPROVIDED] = LIVE, /* refused as not provided, whatever the state */
};

const char *phase_name(Phase phase)
{
    static const char *NAMES[PHASE_COUNT] = {
        "instantiated", "initialization mode", "step mode", "terminated", "error",
        "broken (pythonfmu failed fatally; the instance can only be freed)",
    };
    return phase < PHASE_COUNT ? NAMES[phase] : "unknown";
}

int call_allowed(Call call, Phase phase)
{
    return phase < PHASE_COUNT && (ALLOWED[call] & IN(phase)) != 0;
}

int set_allowed(const Variable *v, Phase phase, char *why, size_t n)
{
    int input = strcmp(v->causality, "input") == 0;
    int parameter = strcmp(v->causality, "parameter") == 0;
    int constant = strcmp(v->variability, "constant") == 0;
    int ok;
    switch (phase) {
    case PHASE_INSTANTIATED: /* start values: initial exact or approx, and inputs */
        ok = input || (!constant && (strcmp(v->initial, "exact") == 0 || strcmp(v->initial, "approx") == 0));
        break;
    case PHASE_INITIALIZATION: /* initial exact, and inputs */
        ok = input || (!constant && strcmp(v->initial, "exact") == 0);
        break;
    case PHASE_STEP: /* inputs and tunable parameters */
        ok = input || (parameter && strcmp(v->variability, "tunable") == 0);
        break;
    default:
        ok = 0;
    }
    if (!ok) {
        int ever = input || (!constant && (strcmp(v->initial, "exact") == 0 || strcmp(v->initial, "approx") == 0));
        snprintf(why, n, "it is a %s %s%s%s, %s", v->variability, v->causality, v->initial[0] ? " with initial " : "",
                 v->initial, !ever ? "which cannot be set"
                           : phase == PHASE_STEP ? "which can be set only before fmi2ExitInitializationMode "
                                                   "(in step mode: inputs and tunable parameters)"
                                                 : "which cannot be set in this state");
    }
    return ok;
}

Phase phase_after(Call call, Phase before, fmi2Status status)
{
    if (status == fmi2Fatal) return PHASE_BROKEN;
    int failed = status == fmi2Error;
    switch (call) {
    case CALL_ENTER_INITIALIZATION: return failed ? PHASE_ERROR : PHASE_INITIALIZATION;
    case CALL_EXIT_INITIALIZATION: return failed ? PHASE_ERROR : PHASE_STEP;
    case CALL_DO_STEP: return failed ? PHASE_ERROR : PHASE_STEP;
    case CALL_TERMINATE: return failed ? PHASE_ERROR : PHASE_TERMINATED;
    case CALL_RESET: return failed ? PHASE_ERROR : PHASE_INSTANTIATED;
    default: return before;
    }
}
