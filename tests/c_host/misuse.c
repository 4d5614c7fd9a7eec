/*
 * The misuse scripts of tests/fmu_misuse.py in the C test host (issue 37):
 *
 *     fmu_host --misuse SCRIPT FMU_DIR OTHER_FMU_DIR
 *
 * runs SCRIPT (format: the docstring of tests/fmu_misuse.py) on the extracted FMUs and
 * prints every call whose status differs from the script's. Exit status: 0 all as
 * expected, 1 bad arguments, 5 a status differed.
 */
#include "misuse.h"

#include <dlfcn.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define FUNCTIONS(X)                                                                                     \
    X(Instantiate) X(FreeInstance) X(SetupExperiment) X(EnterInitializationMode) X(ExitInitializationMode) \
    X(Terminate) X(Reset) X(DoStep) X(GetReal) X(GetInteger) X(GetBoolean) X(GetString) X(SetReal)         \
    X(SetInteger) X(SetBoolean) X(SetString) X(GetFMUstate) X(SetFMUstate) X(FreeFMUstate)                 \
    X(SerializedFMUstateSize) X(SerializeFMUstate) X(DeSerializeFMUstate) X(GetDirectionalDerivative)

typedef struct {
#define MEMBER(name) fmi2##name##TYPE *name;
    FUNCTIONS(MEMBER)
#undef MEMBER
    char guid[128];
    char uri[4200];
    void *lib;
} Fmu;

#define SLOTS 16

typedef struct {
    Fmu fmus[2];
    const Fmu *owner[SLOTS];
    fmi2Component inst[SLOTS];
    fmi2FMUstate states[SLOTS];
    unsigned char *bytes[SLOTS];
    size_t size[SLOTS];
} World;

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env, (void)category;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s] status %d: ", instance ? instance : "?", (int)status);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

/* The value of attribute key (first occurrence) in text into out. */
static int xml_attribute(const char *text, const char *key, char *out, size_t n)
{
    const char *p = strstr(text, key);
    if (!p) return 0;
    p += strlen(key);
    const char *end = strchr(p, '"');
    if (!end) return 0;
    snprintf(out, n, "%.*s", (int)(end - p), p);
    return 1;
}

static int load(Fmu *f, const char *dir)
{
    char path[4096], id[256];
    snprintf(path, sizeof path, "%s/modelDescription.xml", dir);
    FILE *file = fopen(path, "rb");
    if (!file) return 0;
    static char text[1 << 20];
    size_t got = fread(text, 1, sizeof text - 1, file);
    fclose(file);
    text[got] = '\0';
    const char *root = strstr(text, "<fmiModelDescription");
    if (!root || !xml_attribute(root, " guid=\"", f->guid, sizeof f->guid)
        || !xml_attribute(text, "modelIdentifier=\"", id, sizeof id))
        return 0;
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", dir, id);
    snprintf(f->uri, sizeof f->uri, "file://%s/resources", dir);
    f->lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!f->lib) {
        fprintf(stderr, "dlopen: %s\n", dlerror());
        return 0;
    }
    int ok = 1;
#define LOAD(name) ok = ok && (*(void **)&f->name = dlsym(f->lib, "fmi2" #name)) != NULL;
    FUNCTIONS(LOAD)
#undef LOAD
    return ok;
}

static uint32_t crc32_ieee(const unsigned char *p, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int k = 0; k < 8; k++) crc = crc & 1 ? 0xEDB88320u ^ (crc >> 1) : crc >> 1;
    }
    return crc ^ 0xFFFFFFFFu;
}

static uint32_t le32(const unsigned char *p) { return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24; }

/* Change byte buffer b as tests/fmu_misuse.py: forge() does. */
static void forge(World *w, int b, const char *mode, const char *arg)
{
    unsigned char *raw = w->bytes[b];
    size_t n = w->size[b];
    unsigned long long k = strtoull(arg, NULL, 10);
    if (!strcmp(mode, "flip") && n) {
        raw[k % n] ^= 0x55;
    } else if (!strcmp(mode, "trunc")) {
        w->size[b] = n ? k % n : 0;
    } else if (!strcmp(mode, "json") || !strcmp(mode, "empty")) {
        static const char json[] = "{\"fmu\": \"TowCable\", \"values\": {}}";
        free(w->bytes[b]);
        w->size[b] = strcmp(mode, "json") ? 0 : sizeof json - 1;
        w->bytes[b] = malloc(sizeof json);
        memcpy(w->bytes[b], json, sizeof json);
    } else if (!strcmp(mode, "copy")) {
        free(w->bytes[b]);
        w->size[b] = w->size[k];
        w->bytes[b] = malloc(w->size[k] + 1);
        if (w->size[k]) memcpy(w->bytes[b], w->bytes[k], w->size[k]);
    } else if (!strcmp(mode, "guid") && n > 24) {
        size_t at = 20 + le32(raw + 16) + 4;
        raw[at] ^= 0x01;
        uint32_t crc = crc32_ieee(raw, n - 4);
        for (int i = 0; i < 4; i++) raw[n - 4 + i] = (unsigned char)(crc >> (8 * i));
    }
}

/* One script line (without the expected status); its status, or -1 if it returns none. */
static int run_op(World *w, const char *op, const char *rest)
{
    int slot = -1, s = -1, b = -1, f = -1;
    unsigned vr = 0;
    double x = 0, y = 0;
    char text[4096] = "";
    static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    if (!strcmp(op, "forge")) {
        char mode[16], arg[32];
        if (sscanf(rest, "%d %15s %31s", &b, mode, arg) == 3 && b >= 0 && b < SLOTS) forge(w, b, mode, arg);
        return -1;
    }
    if (sscanf(rest, "%d", &slot) != 1 || slot < 0 || slot >= SLOTS) return 99;
    if (!strcmp(op, "inst")) {
        if (sscanf(rest, "%d %d %255s", &slot, &f, text) != 3 || f < 0 || f > 1) return 99;
        const Fmu *fmu = &w->fmus[f];
        w->owner[slot] = fmu;
        w->inst[slot] = fmu->Instantiate(text, fmi2CoSimulation, fmu->guid, fmu->uri, &callbacks, fmi2False,
                                         fmi2False);
        return w->inst[slot] ? fmi2OK : fmi2Error;
    }
    const Fmu *fmu = w->owner[slot];
    fmi2Component c = w->inst[slot];
    if (!fmu) return 99;
    if (!strcmp(op, "free")) {
        fmu->FreeInstance(c); /* the slot keeps the stale pointer */
        return -1;
    }
    if (!strcmp(op, "setup")) return sscanf(rest, "%*d %lf", &x) == 1 ? fmu->SetupExperiment(c, 0, 0, x, 0, 0) : 99;
    if (!strcmp(op, "enter")) return fmu->EnterInitializationMode(c);
    if (!strcmp(op, "exit")) return fmu->ExitInitializationMode(c);
    if (!strcmp(op, "term")) return fmu->Terminate(c);
    if (!strcmp(op, "reset")) return fmu->Reset(c);
    if (!strcmp(op, "step")) return sscanf(rest, "%*d %lf %lf", &x, &y) == 2 ? fmu->DoStep(c, x, y, fmi2True) : 99;
    if (!strcmp(op, "unprov")) return fmu->GetDirectionalDerivative(c, NULL, 0, NULL, 0, NULL, NULL);
    if (!strcmp(op, "getr_null")) {
        fmi2Real value;
        return fmu->GetReal(c, NULL, 1, &value);
    }
    if (!strncmp(op, "set", 3) && strlen(op) == 4) {
        int offset = 0;
        if (sscanf(rest, "%*d %u %n", &vr, &offset) != 1) return 99;
        const char *value = rest + offset;
        fmi2Integer integer = (fmi2Integer)strtol(value, NULL, 10);
        fmi2Real real = strtod(value, NULL);
        switch (op[3]) {
        case 'r': return fmu->SetReal(c, &vr, 1, &real);
        case 'i': return fmu->SetInteger(c, &vr, 1, &integer);
        case 'b': return fmu->SetBoolean(c, &vr, 1, &integer);
        case 's': return fmu->SetString(c, &vr, 1, &value);
        default: return 99;
        }
    }
    if (!strncmp(op, "get", 3) && strlen(op) == 4) {
        if (sscanf(rest, "%*d %u", &vr) != 1) return 99;
        fmi2Real real;
        fmi2Integer integer;
        fmi2String string;
        switch (op[3]) {
        case 'r': return fmu->GetReal(c, &vr, 1, &real);
        case 'i': return fmu->GetInteger(c, &vr, 1, &integer);
        case 'b': return fmu->GetBoolean(c, &vr, 1, &integer);
        case 's': return fmu->GetString(c, &vr, 1, &string);
        default: return 99;
        }
    }
    if (!strcmp(op, "record")) {
        fmi2ValueReference vrs[256];
        fmi2Real values[256];
        size_t n = 0;
        const char *p = strchr(rest, ' ');
        while (p && n < 256) {
            vrs[n++] = (fmi2ValueReference)strtoul(p + 1, NULL, 10);
            p = strchr(p + 1, ',');
        }
        return fmu->GetReal(c, vrs, n, values);
    }
    if (sscanf(rest, "%*d %d %d", &s, &b) < 1 || s < 0 || s >= SLOTS) return 99;
    if (!strcmp(op, "gstate")) {
        w->states[s] = NULL;
        return fmu->GetFMUstate(c, &w->states[s]);
    }
    if (!strcmp(op, "sstate")) return fmu->SetFMUstate(c, w->states[s]);
    if (!strcmp(op, "fstate")) {
        fmi2FMUstate stale = w->states[s]; /* the slot keeps the stale pointer */
        return fmu->FreeFMUstate(c, &stale);
    }
    if (!strcmp(op, "ser") || !strcmp(op, "ser_small")) {
        size_t size = 0;
        int status = fmu->SerializedFMUstateSize(c, w->states[s], &size);
        if (status > fmi2Warning) return status;
        int small = !strcmp(op, "ser_small");
        unsigned char *raw = malloc(size + 1);
        int second = fmu->SerializeFMUstate(c, w->states[s], (fmi2Byte *)raw, size - (size_t)small);
        if (second > status) status = second;
        if (!small && b >= 0 && b < SLOTS) {
            free(w->bytes[b]);
            w->bytes[b] = raw;
            w->size[b] = size;
        } else {
            free(raw);
        }
        return status;
    }
    if (!strcmp(op, "deser")) { /* deser I B S: the byte slot first */
        if (b < 0 || b >= SLOTS) return 99;
        w->states[b] = NULL;
        unsigned char none = 0;
        return fmu->DeSerializeFMUstate(c, w->bytes[s] ? (const fmi2Byte *)w->bytes[s] : (const fmi2Byte *)&none,
                                        w->size[s], &w->states[b]);
    }
    return 99;
}

int misuse_main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: fmu_host --misuse SCRIPT FMU_DIR OTHER_FMU_DIR\n");
        return 1;
    }
    static World w;
    if (!load(&w.fmus[0], argv[1]) || !load(&w.fmus[1], argv[2])) {
        fprintf(stderr, "cannot load the FMUs %s and %s\n", argv[1], argv[2]);
        return 1;
    }
    FILE *script = fopen(argv[0], "r");
    if (!script) return 1;
    char line[8192];
    int number = 0, mismatches = 0;
    while (fgets(line, sizeof line, script)) {
        line[strcspn(line, "\r\n")] = '\0';
        char expected[8], op[32];
        int offset = 0;
        if (sscanf(line, "%7s %31s %n", expected, op, &offset) != 2) continue;
        int status = run_op(&w, op, line + offset);
        if (strcmp(expected, "-") != 0 && status != atoi(expected)) {
            printf("line %d: %s -> status %d\n", number, line, status);
            mismatches++;
        }
        number++;
    }
    fclose(script);
    for (int i = 0; i < SLOTS; i++) free(w.bytes[i]);
    printf("%d calls, %d statuses other than expected\n", number, mismatches);
    return mismatches ? 5 : 0;
}
