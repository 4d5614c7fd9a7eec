/* The envelope of serialised FMU states (see state_bytes.h). */
#include "state_bytes.h"

#include <stdio.h>
#include <string.h>

#define MAGIC "TWCSTATE"
#define MAGIC_SIZE 8
#define FORMAT 1u

static uint32_t crc32_ieee(const unsigned char *p, size_t n)
{
    static uint32_t table[256];
    static int ready = 0; /* the table is the same whoever fills it: a race is harmless */
    if (!ready) {
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t c = i;
            for (int k = 0; k < 8; k++) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            table[i] = c;
        }
        ready = 1;
    }
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
    return crc ^ 0xFFFFFFFFu;
}

static unsigned char *put(unsigned char *out, uint64_t value, int bytes)
{
    for (int i = 0; i < bytes; i++) *out++ = (unsigned char)(value >> (8 * i));
    return out;
}

static uint64_t get(const unsigned char *in, int bytes)
{
    uint64_t value = 0;
    for (int i = 0; i < bytes; i++) value |= (uint64_t)in[i] << (8 * i);
    return value;
}

size_t state_bytes_size(const char *name, const char *guid, size_t payload)
{
    return MAGIC_SIZE + 4 + 4 + 4 + strlen(name) + 4 + strlen(guid) + 8 + payload + 4;
}

void state_bytes_write(unsigned char *out, const char *name, const char *guid, uint32_t phase,
                       const unsigned char *payload, size_t payload_size)
{
    unsigned char *p = out;
    memcpy(p, MAGIC, MAGIC_SIZE);
    p = put(p + MAGIC_SIZE, FORMAT, 4);
    p = put(p, phase, 4);
    p = put(p, strlen(name), 4);
    memcpy(p, name, strlen(name));
    p = put(p + strlen(name), strlen(guid), 4);
    memcpy(p, guid, strlen(guid));
    p = put(p + strlen(guid), payload_size, 8);
    if (payload_size) memcpy(p, payload, payload_size);
    p += payload_size;
    put(p, crc32_ieee(out, (size_t)(p - out)), 4);
}

/* A length-prefixed string at *at equal to expected (what, for the message)? Advances *at. */
static int field(const unsigned char *bytes, size_t size, size_t *at, const char *expected, const char *what,
                 char *err, size_t n)
{
    if (size - *at < 4) {
        snprintf(err, n, "the bytes end inside the %s (truncated)", what);
        return 0;
    }
    uint64_t length = get(bytes + *at, 4);
    *at += 4;
    if (length > size - *at) {
        snprintf(err, n, "the %s is longer than the bytes (truncated or corrupt)", what);
        return 0;
    }
    if (length != strlen(expected) || memcmp(bytes + *at, expected, length) != 0) {
        snprintf(err, n, "the state is of %s '%.*s', this FMU's is '%s'", what, (int)(length > 80 ? 80 : length),
                 (const char *)bytes + *at, expected);
        return 0;
    }
    *at += length;
    return 1;
}

int state_bytes_read(const unsigned char *bytes, size_t size, const char *name, const char *guid, uint32_t *phase,
                     const unsigned char **payload, size_t *payload_size, char *err, size_t n)
{
    size_t at = MAGIC_SIZE + 8;
    if (size < at || memcmp(bytes, MAGIC, MAGIC_SIZE) != 0) {
        snprintf(err, n, "the %zu bytes are not a towcable FMU state (they do not start with \"" MAGIC "\")",
                 size);
        return 0;
    }
    if (size < 4 || get(bytes + size - 4, 4) != crc32_ieee(bytes, size - 4)) {
        snprintf(err, n, "the checksum of the %zu bytes does not match (corrupt or truncated)", size);
        return 0;
    }
    if (get(bytes + MAGIC_SIZE, 4) != FORMAT) {
        snprintf(err, n, "the state's format %u is not this FMU's (%u)", (unsigned)get(bytes + MAGIC_SIZE, 4),
                 FORMAT);
        return 0;
    }
    size -= 4; /* the checksum */
    *phase = (uint32_t)get(bytes + MAGIC_SIZE + 4, 4);
    if (!field(bytes, size, &at, name, "FMU", err, n) || !field(bytes, size, &at, guid, "GUID (build)", err, n))
        return 0;
    if (size - at < 8 || get(bytes + at, 8) != size - at - 8) {
        snprintf(err, n, "the payload length does not match the bytes (truncated or corrupt)");
        return 0;
    }
    *payload = bytes + at + 8;
    *payload_size = size - at - 8;
    return 1;
}
