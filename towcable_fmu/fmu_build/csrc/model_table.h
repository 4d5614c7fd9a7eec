/*
 * The variables of an FMU as its modelDescription.xml declares them (for the state
 * machine's checks in fmu_loader.c): value reference, type, causality, variability,
 * initial and name, found by (type, value reference) in constant time.
 */
#ifndef TOWCABLE_MODEL_TABLE_H
#define TOWCABLE_MODEL_TABLE_H

#include <stddef.h>

#include "fmi2Functions.h"

typedef enum { TYPE_REAL, TYPE_INTEGER, TYPE_BOOLEAN, TYPE_STRING, TYPE_OTHER } VariableType;

typedef struct {
    fmi2ValueReference vr;
    VariableType type;
    char causality[24];   /* parameter, input, output, local, ... (the XML's words) */
    char variability[16]; /* constant, fixed, tunable, discrete, continuous */
    char initial[12];     /* exact, approx, calculated, or "" */
    char name[160];
    unsigned settable;    /* bit p: may be set in phase p (filled by the loader from state_machine.h) */
    int parameter;        /* causality parameter */
    int input;            /* causality input */
} Variable;

typedef struct {
    char guid[96];
    Variable *variables;  /* (the loader fills settable and parameter) */
    size_t count;
    int *index;           /* value reference -> position in variables, -1: none */
    size_t index_size;
} ModelTable;

/* Read root/resources/modelDescription.xml (the build's copy of the FMU's) into table; 0
   with a message in err if it cannot. */
int model_table_read(const char *root, ModelTable *table, char *err, size_t n);

/* The variable of this type and value reference, or NULL. */
const Variable *model_table_find(const ModelTable *table, VariableType type, fmi2ValueReference vr);

/* A whole text file in a new NUL-terminated buffer (NULL if it cannot be read). */
char *read_text_file(const char *path);

/* "Real", "Integer", ... */
const char *type_name(VariableType type);

#endif
