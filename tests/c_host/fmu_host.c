/*
 * A minimal FMI 2.0 Co-Simulation host without Python, for tests/test_fmu_native.py.
 *
 *     fmu_host FMU_DIR PLAN OUT.csv
 *
 * FMU_DIR is an extracted FMU. PLAN is a text file, one directive a line:
 *
 *     model ID            modelIdentifier (loads FMU_DIR/binaries/linux64/ID.so)
 *     guid GUID
 *     start T0 / stop T1 / step H   communication grid [s]
 *     instances N          run the whole sequence N times, one instance after the other
 *     logging on|off       the loggingOn argument of fmi2Instantiate (default on)
 *     inputs FILE.csv      header line, then rows "time,u1,u2,..." on the grid t0 + k H
 *     input VR             value reference of the next input column (Real)
 *     param R VR VALUE / param S VR TEXT   set after fmi2Instantiate
 *     output R VR NAME / output B VR NAME  columns of OUT.csv
 *
 * Each instance: fmi2Instantiate, parameters, fmi2SetupExperiment(t0, t1),
 * fmi2EnterInitializationMode, inputs of row 0, fmi2ExitInitializationMode, outputs at
 * t0; then for k = 0, 1, ...: inputs of row k, fmi2DoStep(t_k, t_{k+1} - t_k), outputs at
 * t_{k+1}, with t_k = t0 + k H (the calls and arguments of fmpy's simulate_fmu: each step
 * ends exactly where the next one starts, whereas t_k + H is t_{k+1} only to an ulp, and
 * a stiff model turns that difference of its clock into 1e-4 N within 10 s);
 * fmi2Terminate (if no call failed: after an error
 * FMI 2.0 allows only fmi2Reset and fmi2FreeInstance), fmi2FreeInstance. OUT.csv holds
 * the first instance's outputs; the largest difference of a later instance to them is
 * printed. Exit status: 0 all calls fmi2OK, 1 bad arguments, 2 fmi2Instantiate failed,
 * 3 another FMI call failed, 4 a later instance differs.
 *
 *     fmu_host --misuse SCRIPT FMU_DIR OTHER_FMU_DIR
 *
 * runs a misuse script instead (misuse.c, issue 37).
 */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "misuse.h"

#define LINE 4096
#define MAX_VARS 64

typedef struct {
    char model[256], guid[256], inputs[LINE];
    double start, stop, step;
    int instances;
    int logging;
    size_t nin, nreal, nbool, nparam;
    fmi2ValueReference in_vr[MAX_VARS], real_vr[MAX_VARS], bool_vr[MAX_VARS], param_vr[MAX_VARS];
    char real_name[MAX_VARS][128], bool_name[MAX_VARS][128], param_type[MAX_VARS];
    char param_value[MAX_VARS][LINE];
} Plan;

typedef struct {
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInitializationMode;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2TerminateTYPE *Terminate;
    fmi2SetRealTYPE *SetReal;
    fmi2SetStringTYPE *SetString;
    fmi2GetRealTYPE *GetReal;
    fmi2GetBooleanTYPE *GetBoolean;
    fmi2DoStepTYPE *DoStep;
} Api;

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...)
{
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s] status %d %s: ", instance ? instance : "?", (int)status, category ? category : "");
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static int read_plan(const char *path, Plan *plan)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[LINE], key[32], kind;
    unsigned vr;
    int offset, ok = 1;
    plan->instances = 1;
    plan->logging = 1;
    while (ok && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (sscanf(line, "%31s %n", key, &offset) != 1) continue;
        const char *rest = line + offset;
        if (!strcmp(key, "model")) ok = sscanf(rest, "%255s", plan->model) == 1;
        else if (!strcmp(key, "guid")) ok = sscanf(rest, "%255s", plan->guid) == 1;
        else if (!strcmp(key, "start")) ok = sscanf(rest, "%lf", &plan->start) == 1;
        else if (!strcmp(key, "stop")) ok = sscanf(rest, "%lf", &plan->stop) == 1;
        else if (!strcmp(key, "step")) ok = sscanf(rest, "%lf", &plan->step) == 1 && plan->step > 0;
        else if (!strcmp(key, "instances")) ok = sscanf(rest, "%d", &plan->instances) == 1;
        else if (!strcmp(key, "logging")) {
            ok = !strcmp(rest, "on") || !strcmp(rest, "off");
            plan->logging = !strcmp(rest, "on");
        }
        else if (!strcmp(key, "inputs")) snprintf(plan->inputs, sizeof plan->inputs, "%s", rest);
        else if (!strcmp(key, "input") && plan->nin < MAX_VARS)
            ok = sscanf(rest, "%u", &plan->in_vr[plan->nin++]) == 1;
        else if (!strcmp(key, "param") && plan->nparam < MAX_VARS
                 && sscanf(rest, "%c %u %n", &kind, &vr, &offset) == 2 && (kind == 'R' || kind == 'S')) {
            plan->param_type[plan->nparam] = kind;
            plan->param_vr[plan->nparam] = vr;
            snprintf(plan->param_value[plan->nparam++], LINE, "%s", rest + offset);
        } else if (!strcmp(key, "output") && sscanf(rest, "%c %u %n", &kind, &vr, &offset) == 2
                   && (kind == 'R' ? plan->nreal : plan->nbool) < MAX_VARS) {
            if (kind == 'R') {
                plan->real_vr[plan->nreal] = vr;
                snprintf(plan->real_name[plan->nreal++], 128, "%s", rest + offset);
            } else if (kind == 'B') {
                plan->bool_vr[plan->nbool] = vr;
                snprintf(plan->bool_name[plan->nbool++], 128, "%s", rest + offset);
            } else {
                ok = 0;
            }
        } else {
            ok = 0;
        }
        if (!ok) fprintf(stderr, "bad plan line: %s\n", line);
    }
    fclose(f);
    return ok && plan->model[0] && plan->stop > plan->start;
}

/* Rows of the input CSV (time + plan->nin values each), *nrows set; NULL on error. */
static double *read_inputs(const Plan *plan, size_t *nrows)
{
    FILE *f = fopen(plan->inputs, "r");
    if (!f) return NULL;
    size_t width = plan->nin + 1, cap = 0, n = 0;
    double *rows = NULL;
    char line[LINE];
    int ok = fgets(line, sizeof line, f) != NULL; /* header */
    while (ok && fgets(line, sizeof line, f)) {
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            double *grown = realloc(rows, cap * width * sizeof *rows);
            if (!grown) {
                ok = 0;
                break;
            }
            rows = grown;
        }
        char *p = line, *end;
        for (size_t j = 0; ok && j < width; j++) {
            rows[n * width + j] = strtod(p, &end);
            ok = end != p && (*end == ',' || j + 1 == width);
            p = end + 1;
        }
        n++;
    }
    fclose(f);
    if (!ok) {
        free(rows);
        return NULL;
    }
    *nrows = n;
    return rows;
}

static int set_inputs(const Api *api, fmi2Component c, const Plan *plan, const double *rows,
                      size_t nrows, size_t k, double t)
{
    if (plan->nin == 0) return 1;
    if (k >= nrows || fabs(rows[k * (plan->nin + 1)] - t) > 1e-9 * (1 + fabs(t))) {
        fprintf(stderr, "input row %zu is not at t = %.17g\n", k, t);
        return 0;
    }
    return api->SetReal(c, plan->in_vr, plan->nin, rows + k * (plan->nin + 1) + 1) == fmi2OK;
}

static int record(const Api *api, fmi2Component c, const Plan *plan, double *row)
{
    fmi2Boolean flags[MAX_VARS];
    if (api->GetReal(c, plan->real_vr, plan->nreal, row) != fmi2OK) return 0;
    if (plan->nbool && api->GetBoolean(c, plan->bool_vr, plan->nbool, flags) != fmi2OK) return 0;
    for (size_t j = 0; j < plan->nbool; j++) row[plan->nreal + j] = flags[j] ? 1.0 : 0.0;
    return 1;
}

/* One instance through the whole sequence; its outputs in out (rows of nreal + nbool). */
static int run(const Api *api, const Plan *plan, const char *uri, const double *inputs,
               size_t nrows, int index, double *out, size_t steps)
{
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    char name[300];
    snprintf(name, sizeof name, "%s_%d", plan->model, index);
    fmi2Component c = api->Instantiate(name, fmi2CoSimulation, plan->guid, uri, &callbacks, fmi2False,
                                     plan->logging ? fmi2True : fmi2False);
    if (!c) {
        fprintf(stderr, "fmi2Instantiate failed\n");
        return 2;
    }
    size_t width = plan->nreal + plan->nbool;
    int ok = 1;
    for (size_t i = 0; ok && i < plan->nparam; i++) {
        if (plan->param_type[i] == 'R') {
            fmi2Real value = strtod(plan->param_value[i], NULL);
            ok = api->SetReal(c, &plan->param_vr[i], 1, &value) == fmi2OK;
        } else {
            fmi2String value = plan->param_value[i];
            ok = api->SetString(c, &plan->param_vr[i], 1, &value) == fmi2OK;
        }
    }
    ok = ok && api->SetupExperiment(c, fmi2False, 0.0, plan->start, fmi2True, plan->stop) == fmi2OK;
    ok = ok && api->EnterInitializationMode(c) == fmi2OK;
    ok = ok && set_inputs(api, c, plan, inputs, nrows, 0, plan->start);
    ok = ok && api->ExitInitializationMode(c) == fmi2OK;
    ok = ok && record(api, c, plan, out);
    for (size_t k = 0; ok && k < steps; k++) {
        double t = plan->start + (double)k * plan->step, next = plan->start + (double)(k + 1) * plan->step;
        ok = set_inputs(api, c, plan, inputs, nrows, k, t)
             && api->DoStep(c, t, next - t, fmi2True) == fmi2OK
             && record(api, c, plan, out + (k + 1) * width);
    }
    ok = ok && api->Terminate(c) == fmi2OK;
    api->FreeInstance(c);
    return ok ? 0 : 3;
}

static int write_csv(const char *path, const Plan *plan, const double *out, size_t steps)
{
    FILE *f = fopen(path, "w");
    if (!f) return 0;
    size_t width = plan->nreal + plan->nbool;
    fprintf(f, "time");
    for (size_t j = 0; j < plan->nreal; j++) fprintf(f, ",%s", plan->real_name[j]);
    for (size_t j = 0; j < plan->nbool; j++) fprintf(f, ",%s", plan->bool_name[j]);
    for (size_t k = 0; k <= steps; k++) {
        fprintf(f, "\n%.17g", plan->start + (double)k * plan->step);
        for (size_t j = 0; j < width; j++) fprintf(f, ",%.17g", out[k * width + j]);
    }
    fputc('\n', f);
    return fclose(f) == 0;
}

int main(int argc, char **argv)
{
    static Plan plan;
    if (argc > 1 && strcmp(argv[1], "--misuse") == 0) return misuse_main(argc - 2, argv + 2);
    if (argc != 4 || !read_plan(argv[2], &plan)) {
        fprintf(stderr, "usage: fmu_host FMU_DIR PLAN OUT.csv (see the source for PLAN)\n");
        return 1;
    }
    char path[LINE], uri[LINE + 16];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", argv[1], plan.model);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 1;
    }
    Api api;
    void *symbols[] = {
        dlsym(lib, "fmi2Instantiate"), dlsym(lib, "fmi2FreeInstance"), dlsym(lib, "fmi2SetupExperiment"),
        dlsym(lib, "fmi2EnterInitializationMode"), dlsym(lib, "fmi2ExitInitializationMode"),
        dlsym(lib, "fmi2Terminate"), dlsym(lib, "fmi2SetReal"), dlsym(lib, "fmi2SetString"),
        dlsym(lib, "fmi2GetReal"), dlsym(lib, "fmi2GetBoolean"), dlsym(lib, "fmi2DoStep"),
    };
    for (size_t i = 0; i < sizeof symbols / sizeof *symbols; i++) {
        if (!symbols[i]) {
            fprintf(stderr, "missing FMI function %zu\n", i);
            dlclose(lib);
            return 1;
        }
    }
    _Static_assert(sizeof api == sizeof symbols, "one symbol per Api member");
    memcpy(&api, symbols, sizeof api);
    snprintf(uri, sizeof uri, "file://%s/resources", argv[1]);

    size_t nrows = 0, steps = (size_t)llround((plan.stop - plan.start) / plan.step);
    double *inputs = NULL;
    if (plan.nin && !(inputs = read_inputs(&plan, &nrows))) {
        fprintf(stderr, "cannot read the inputs %s\n", plan.inputs);
        dlclose(lib);
        return 1;
    }
    size_t width = plan.nreal + plan.nbool;
    double *first = calloc((steps + 1) * width, sizeof *first);
    double *again = calloc((steps + 1) * width, sizeof *again);
    int status = first && again ? run(&api, &plan, uri, inputs, nrows, 1, first, steps) : 1;
    if (status == 0 && !write_csv(argv[3], &plan, first, steps)) status = 1;
    for (int i = 2; status == 0 && i <= plan.instances; i++) {
        status = run(&api, &plan, uri, inputs, nrows, i, again, steps);
        double diff = 0.0;
        for (size_t j = 0; j < (steps + 1) * width; j++) diff = fmax(diff, fabs(again[j] - first[j]));
        printf("instance %d: largest difference to instance 1: %.17g\n", i, diff);
        if (status == 0 && diff != 0.0) status = 4;
    }
    free(first);
    free(again);
    free(inputs);
    dlclose(lib);
    return status;
}
