/*
 * The values an instance shares with its Python slave (towcable_fmu/fmi/shared_values.py
 * mirrors this layout with ctypes): while `served` is 1 the loader answers fmi2Get*
 * of Real, Integer and Boolean variables from `values`, keeps fmi2SetReal of inputs in
 * it, and makes fmi2DoStep with the slave's compiled `step` if it has one; every other
 * call (and a compiled function that declines) goes to the slave, which first takes
 * the values back (served = 0) and hands them over again at the end of its entry point.
 *
 * The loader allocates it per instance and hands it over only to the slave it is
 * creating: towcable_shared_values() answers during fmi2Instantiate and fmi2Reset, on
 * their thread, and NULL otherwise (no FMI call reaches it).
 */
#ifndef TOWCABLE_SHARED_VALUES_H
#define TOWCABLE_SHARED_VALUES_H

#include <stdint.h>

#define SHARED_VALUES_VERSION 1

/* A compiled step from t by h [s]: reads its inputs from and writes its outputs into
   values (indexed by value reference); 0 if done, else it changed nothing and the step
   goes to Python (which reports what is wrong). With direct feedthrough the loader has
   made the outputs of the inputs first (CompiledOutputs). */
typedef int32_t (*CompiledStep)(double *values, const double *model, double t, double h);
/* The outputs of the current inputs (a slave with direct feedthrough); 0 if done, else
   nothing changed and the call goes to Python. */
typedef int32_t (*CompiledOutputs)(double *values, const double *model);

typedef struct {
    uint32_t version;        /* SHARED_VALUES_VERSION */
    int32_t served;          /* 1: the loader serves from values; 0: the slave holds the values */
    int32_t inputs_set;      /* inputs were set into values since the slave last took them */
    int32_t outputs_stale;   /* inputs were set since the outputs were computed (feedthrough) */
    uint64_t compiled_steps; /* steps made with `step` */
    double time;             /* the communication point the next step starts from [s] */
    int64_t timer_vr;        /* the model wall time output [s] the compiled calls add to (-1: none) */
    CompiledStep step;       /* NULL: steps go to the slave */
    CompiledOutputs outputs; /* NULL: no direct feedthrough (or not compiled) */
    const double *model;     /* the compiled functions' data (the slave keeps it alive) */
    uint64_t count;          /* values: value references 0 .. count - 1 */
    double values[];         /* Real, Integer and Boolean values by value reference */
} SharedValues;

/* The shared values of the instance being instantiated or reset on this thread (NULL
   outside fmi2Instantiate and fmi2Reset). */
__attribute__((visibility("default"))) SharedValues *towcable_shared_values(void);

#endif
