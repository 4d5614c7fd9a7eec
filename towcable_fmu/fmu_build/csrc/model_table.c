/*
 * modelDescription.xml read with a small scanner: the root element's guid and each
 * ScalarVariable's attributes and type element. The file is the copy in resources/ (a
 * host need not extract the archive's root file), written by
 * towcable_fmu/fmu_build/build.py (ElementTree: attribute values escape '"', '<' and '>'), so
 * an attribute is ` key="value"` inside its start tag.
 */
#include "model_table.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_VALUE_REFERENCE 1000000u

char *read_text_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (size = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0)
        text = malloc((size_t)size + 1);
    if (text && fread(text, 1, (size_t)size, f) == (size_t)size) {
        text[size] = '\0';
    } else {
        free(text);
        text = NULL;
    }
    fclose(f);
    return text;
}

/* Attribute key of the start tag [tag, end) into out; 0 if it has none. */
static int attribute(const char *tag, const char *end, const char *key, char *out, size_t n)
{
    size_t k = strlen(key);
    for (const char *p = tag + 1; p + k + 2 < end; p++) {
        if ((p[-1] == ' ' || p[-1] == '\n' || p[-1] == '\t') && strncmp(p, key, k) == 0 && p[k] == '='
            && p[k + 1] == '"') {
            const char *value = p + k + 2;
            const char *close = memchr(value, '"', (size_t)(end - value));
            if (!close) return 0;
            snprintf(out, n, "%.*s", (int)(close - value), value);
            return 1;
        }
    }
    return 0;
}

static VariableType type_of(const char *element)
{
    static const struct { const char *tag; VariableType type; } TYPES[] = {
        {"<Real", TYPE_REAL}, {"<Integer", TYPE_INTEGER}, {"<Boolean", TYPE_BOOLEAN}, {"<String", TYPE_STRING},
    };
    for (size_t i = 0; i < sizeof TYPES / sizeof *TYPES; i++) {
        size_t k = strlen(TYPES[i].tag);
        if (strncmp(element, TYPES[i].tag, k) == 0 && strchr(" />\n\t", element[k])) return TYPES[i].type;
    }
    return TYPE_OTHER;
}

const char *type_name(VariableType type)
{
    static const char *NAMES[] = {"Real", "Integer", "Boolean", "String", "other"};
    return NAMES[type];
}

static int parse(const char *text, ModelTable *table, char *err, size_t n)
{
    const char *root = strstr(text, "<fmiModelDescription");
    const char *root_end = root ? strchr(root, '>') : NULL;
    if (!root_end || !attribute(root, root_end, "guid", table->guid, sizeof table->guid)) {
        snprintf(err, n, "no fmiModelDescription element with a guid");
        return 0;
    }
    size_t cap = 0;
    fmi2ValueReference largest = 0;
    for (const char *p = strstr(root_end, "<ScalarVariable"); p; p = strstr(p + 1, "<ScalarVariable")) {
        const char *end = strchr(p, '>');
        if (!end) break;
        if (table->count == cap) {
            cap = cap ? 2 * cap : 64;
            Variable *grown = realloc(table->variables, cap * sizeof *grown);
            if (!grown) {
                snprintf(err, n, "out of memory");
                return 0;
            }
            table->variables = grown;
        }
        Variable *v = &table->variables[table->count];
        memset(v, 0, sizeof *v);
        char vr[32];
        char *tail = NULL;
        unsigned long value = 0;
        if (attribute(p, end, "valueReference", vr, sizeof vr)) value = strtoul(vr, &tail, 10);
        if (!tail || *tail || value > MAX_VALUE_REFERENCE || !attribute(p, end, "name", v->name, sizeof v->name)) {
            snprintf(err, n, "a ScalarVariable without a name or a valueReference up to %u", MAX_VALUE_REFERENCE);
            return 0;
        }
        v->vr = (fmi2ValueReference)value;
        if (!attribute(p, end, "causality", v->causality, sizeof v->causality)) strcpy(v->causality, "local");
        if (!attribute(p, end, "variability", v->variability, sizeof v->variability))
            strcpy(v->variability, "continuous");
        attribute(p, end, "initial", v->initial, sizeof v->initial);
        const char *child = end + 1;
        while (*child == ' ' || *child == '\n' || *child == '\t' || *child == '\r') child++;
        v->type = type_of(child);
        if (v->vr > largest) largest = v->vr;
        table->count++;
    }
    table->index_size = (size_t)largest + 1;
    table->index = malloc(table->index_size * sizeof *table->index);
    if (!table->index) {
        snprintf(err, n, "out of memory");
        return 0;
    }
    for (size_t i = 0; i < table->index_size; i++) table->index[i] = -1;
    for (size_t i = table->count; i-- > 0;) table->index[table->variables[i].vr] = (int)i;
    return 1;
}

int model_table_read(const char *root, ModelTable *table, char *err, size_t n)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/resources/modelDescription.xml", root);
    memset(table, 0, sizeof *table);
    char *text = read_text_file(path);
    if (!text) {
        snprintf(err, n, "cannot read %s", path);
        return 0;
    }
    char why[256] = "";
    int ok = parse(text, table, why, sizeof why);
    free(text);
    if (!ok) {
        snprintf(err, n, "%s: %s", path, why);
        free(table->variables);
        free(table->index);
        memset(table, 0, sizeof *table);
    }
    return ok;
}

const Variable *model_table_find(const ModelTable *table, VariableType type, fmi2ValueReference vr)
{
    if (vr >= table->index_size || table->index[vr] < 0) return NULL;
    const Variable *v = &table->variables[table->index[vr]];
    if (v->type == type) return v;
    for (size_t i = 0; i < table->count; i++) /* one value reference for several types */
        if (table->variables[i].vr == vr && table->variables[i].type == type) return &table->variables[i];
    return NULL;
}
