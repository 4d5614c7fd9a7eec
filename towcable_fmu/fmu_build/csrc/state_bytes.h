/*
 * Serialised FMU states: pythonfmu's bytes (the slave's JSON) in an envelope that says
 * which FMU and build they belong to and carries a checksum. Layout (integers
 * little-endian):
 *
 *     "TWCSTATE" | format u32 (1) | phase u32 | name length u32 | name |
 *     GUID length u32 | GUID | payload length u64 | payload | CRC-32 (IEEE) u32
 *
 * name is the FMU's modelIdentifier, GUID that of its modelDescription.xml (a digest
 * of the archive's content, towcable_fmu/fmu_build/build.py), phase the state machine's
 * state when the state was taken, and the CRC covers every byte before it.
 */
#ifndef TOWCABLE_STATE_BYTES_H
#define TOWCABLE_STATE_BYTES_H

#include <stddef.h>
#include <stdint.h>

/* Bytes of the envelope around a payload of this size. */
size_t state_bytes_size(const char *name, const char *guid, size_t payload);

/* Write the envelope (state_bytes_size bytes) into out. */
void state_bytes_write(unsigned char *out, const char *name, const char *guid, uint32_t phase,
                       const unsigned char *payload, size_t payload_size);

/* Check bytes against the FMU name and GUID; on success the phase and the payload (a
   part of bytes), else 0 and the reason in err. */
int state_bytes_read(const unsigned char *bytes, size_t size, const char *name, const char *guid, uint32_t *phase,
                     const unsigned char **payload, size_t *payload_size, char *err, size_t n);

#endif
