/*
 * clino wire protocol v1, board side and host side, in plain C (C99).
 *
 * The specification is PROTOCOL.md / protocol-spec: every frame on the wire is
 * COBS(body) ++ 0x00, body = type:u8 ++ payload ++ crc:u16 (little-endian),
 * crc = CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, xorout 0)
 * over type ++ payload. Multi-byte fields are little-endian. A body is at most
 * 64 bytes, so an encoded frame is at most 66 bytes with its delimiter.
 *
 * This file has no AVR dependency: the firmware, the simavr harness and the
 * host unit test compile the same code.
 */
#ifndef CLINO_PROTOCOL_H
#define CLINO_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PROTO_VERSION 1u
#define PROTO_MAX_BODY 64u
#define PROTO_MAX_PAYLOAD (PROTO_MAX_BODY - 3u)
/* COBS adds one byte per 254 (and at least one); plus the 0x00 delimiter. */
#define PROTO_MAX_WIRE (PROTO_MAX_BODY + 2u)

/* Frame types, board -> host. */
#define PROTO_CONFIG 0x01u
#define PROTO_SAMPLE 0x02u
#define PROTO_ACK 0x03u
/* Frame types, host -> board. */
#define PROTO_REQUEST_CONFIG 0x10u
#define PROTO_SET_RATE 0x11u
#define PROTO_SET_RANGES 0x12u
#define PROTO_START 0x13u
#define PROTO_STOP 0x14u
#define PROTO_SET_DIALS 0x15u

/* Payload lengths of the known types. */
#define PROTO_CONFIG_LEN 12u
#define PROTO_SAMPLE_LEN 20u
#define PROTO_ACK_LEN 2u
#define PROTO_SET_RATE_LEN 2u
#define PROTO_SET_RANGES_LEN 4u
#define PROTO_SET_DIALS_LEN 4u

/* ACK status codes. */
#define PROTO_ACK_OK 0u
#define PROTO_ACK_RANGE 1u
#define PROTO_ACK_UNKNOWN 2u
#define PROTO_ACK_BAD_FRAME 3u

/* Board identifiers in CONFIG. */
#define PROTO_BOARD_UNO 1u
#define PROTO_BOARD_CORTEX_M4F 2u
#define PROTO_BOARD_HOST_SIM 3u

/* CRC-16/CCITT-FALSE of len bytes; check value of "123456789" is 0x29B1. */
uint16_t proto_crc16(const uint8_t *data, size_t len);
/* Continue a CRC over more bytes (start with 0xFFFF). */
uint16_t proto_crc16_update(uint16_t crc, const uint8_t *data, size_t len);

/*
 * COBS-encode len bytes of in into out (no delimiter written). out must hold
 * len + len/254 + 1 bytes. Returns the number of bytes written.
 */
size_t proto_cobs_encode(const uint8_t *in, size_t len, uint8_t *out);

/*
 * COBS-decode len bytes (without the delimiter) into out, which holds cap
 * bytes. Returns the decoded length, or -1 if the input holds a zero byte,
 * a code runs past the end, or the result would not fit.
 */
int proto_cobs_decode(const uint8_t *in, size_t len, uint8_t *out, size_t cap);

/*
 * Build a complete wire frame (COBS(type ++ payload ++ crc) ++ 0x00) into out,
 * which must hold PROTO_MAX_WIRE bytes. Returns the wire length, or 0 if
 * plen > PROTO_MAX_PAYLOAD.
 */
size_t proto_frame(uint8_t type, const uint8_t *payload, size_t plen, uint8_t *out);

/* Decoded contents of the board's frames. */
typedef struct {
    uint8_t proto_version, fw_major, fw_minor, fw_patch, board;
    uint16_t rate_hz;
    uint8_t accel_fs_g;
    uint16_t gyro_fs_dps;
    uint8_t dlpf_cfg, streaming;
} proto_config_t;

typedef struct {
    uint16_t seq;
    uint32_t t_us;
    int16_t ax, ay, az, temp, gx, gy, gz;
} proto_sample_t;

size_t proto_frame_config(const proto_config_t *c, uint8_t *out);
size_t proto_frame_sample(const proto_sample_t *s, uint8_t *out);
size_t proto_frame_ack(uint8_t command, uint8_t status, uint8_t *out);

/* Parse payloads (lengths already checked by proto_check_length). */
void proto_parse_config(const uint8_t *p, proto_config_t *c);
void proto_parse_sample(const uint8_t *p, proto_sample_t *s);

/*
 * The payload length the spec fixes for a type, or -1 for a type the
 * protocol does not define.
 */
int proto_payload_len(uint8_t type);

/* Little-endian field access. */
static inline void proto_put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)(v >> 8);
}
static inline void proto_put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v & 0xFFu);
    p[1] = (uint8_t)((v >> 8) & 0xFFu);
    p[2] = (uint8_t)((v >> 16) & 0xFFu);
    p[3] = (uint8_t)(v >> 24);
}
static inline uint16_t proto_get_u16(const uint8_t *p)
{
    return (uint16_t)((uint16_t)p[0] | ((uint16_t)p[1] << 8));
}
static inline int16_t proto_get_i16(const uint8_t *p)
{
    return (int16_t)proto_get_u16(p);
}
static inline uint32_t proto_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
           ((uint32_t)p[3] << 24);
}

/*
 * Streaming receiver: feed it every byte; it resynchronises on 0x00.
 * proto_rx_push returns PROTO_RX_NONE while a frame is incomplete,
 * PROTO_RX_EMPTY for a lone delimiter (no frame), PROTO_RX_FRAME for a good
 * frame (type in rx->type, payload in rx->body + 1, rx->plen bytes) and
 * PROTO_RX_BAD for a bad one (too long, bad COBS, shorter than 3 bytes, CRC
 * mismatch, unknown type or wrong payload length; rx->bad_reason says which
 * and rx->type holds the type byte when there was one, else 0).
 */
enum { PROTO_RX_NONE = 0, PROTO_RX_EMPTY, PROTO_RX_FRAME, PROTO_RX_BAD };
enum {
    PROTO_BAD_NONE = 0,
    PROTO_BAD_OVERLONG,
    PROTO_BAD_COBS,
    PROTO_BAD_SHORT,
    PROTO_BAD_CRC,
    PROTO_BAD_TYPE,
    PROTO_BAD_LENGTH
};

typedef struct {
    uint8_t raw[PROTO_MAX_WIRE];  /* encoded bytes since the last delimiter */
    uint8_t body[PROTO_MAX_BODY]; /* decoded body of the last frame */
    uint8_t nraw;
    uint8_t overflow; /* the current frame ran past PROTO_MAX_WIRE */
    uint8_t type;
    uint8_t plen;
    uint8_t bad_reason;
    uint32_t frames, bad; /* counters */
} proto_rx_t;

void proto_rx_init(proto_rx_t *rx);
int proto_rx_push(proto_rx_t *rx, uint8_t byte);

#ifdef __cplusplus
}
#endif

#endif
