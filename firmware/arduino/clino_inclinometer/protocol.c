/* clino wire protocol v1: CRC, COBS, frames, receiver. See protocol.h. */
#include "protocol.h"

#include <string.h>

#ifdef __AVR__
#include <util/crc16.h>
#endif

uint16_t proto_crc16_update(uint16_t crc, const uint8_t *data, size_t len)
{
#ifdef __AVR__
    /* avr-libc's XMODEM step is the same polynomial (0x1021), MSB first and
     * unreflected: with init 0xFFFF it is CCITT-FALSE, in 1/4 of the cycles. */
    for (size_t i = 0; i < len; i++)
        crc = _crc_xmodem_update(crc, data[i]);
    return crc;
#endif
    /* CRC-16/CCITT-FALSE, bitwise (MSB first): small and exact on an AVR. */
    for (size_t i = 0; i < len; i++) {
        crc ^= (uint16_t)((uint16_t)data[i] << 8);
        for (uint8_t b = 0; b < 8; b++) {
            if (crc & 0x8000u)
                crc = (uint16_t)((crc << 1) ^ 0x1021u);
            else
                crc = (uint16_t)(crc << 1);
        }
    }
    return crc;
}


uint16_t proto_crc16(const uint8_t *data, size_t len)
{
    return proto_crc16_update(0xFFFFu, data, len);
}

size_t proto_cobs_encode(const uint8_t *in, size_t len, uint8_t *out)
{
    size_t code_at = 0; /* where the current block's code byte goes */
    size_t o = 1;
    uint8_t code = 1;
    for (size_t i = 0; i < len; i++) {
        if (in[i] == 0) {
            out[code_at] = code;
            code_at = o++;
            code = 1;
        } else {
            out[o++] = in[i];
            code++;
            /* A full block (254 data bytes) closes; a new one opens only if
             * more input follows (the canonical encoding, as in Cheshire &
             * Baker's COBS paper). */
            if (code == 0xFF && i + 1 < len) {
                out[code_at] = code;
                code_at = o++;
                code = 1;
            }
        }
    }
    out[code_at] = code;
    return o;
}

int proto_cobs_decode(const uint8_t *in, size_t len, uint8_t *out, size_t cap)
{
    size_t i = 0, o = 0;
    while (i < len) {
        uint8_t code = in[i++];
        if (code == 0)
            return -1;
        for (uint8_t k = 1; k < code; k++) {
            if (i >= len || in[i] == 0 || o >= cap)
                return -1;
            out[o++] = in[i++];
        }
        /* A code below 0xFF stands for a zero, except at the very end. */
        if (code != 0xFF && i < len) {
            if (o >= cap)
                return -1;
            out[o++] = 0;
        }
    }
    return (int)o;
}

size_t proto_frame(uint8_t type, const uint8_t *payload, size_t plen, uint8_t *out)
{
    uint8_t body[PROTO_MAX_BODY];
    if (plen > PROTO_MAX_PAYLOAD)
        return 0;
    body[0] = type;
    if (plen)
        memcpy(body + 1, payload, plen);
    uint16_t crc = proto_crc16(body, plen + 1);
    proto_put_u16(body + 1 + plen, crc);
    size_t n = proto_cobs_encode(body, plen + 3, out);
    out[n++] = 0x00;
    return n;
}

size_t proto_frame_config(const proto_config_t *c, uint8_t *out)
{
    uint8_t p[PROTO_CONFIG_LEN];
    p[0] = c->proto_version;
    p[1] = c->fw_major;
    p[2] = c->fw_minor;
    p[3] = c->fw_patch;
    p[4] = c->board;
    proto_put_u16(p + 5, c->rate_hz);
    p[7] = c->accel_fs_g;
    proto_put_u16(p + 8, c->gyro_fs_dps);
    p[10] = c->dlpf_cfg;
    p[11] = c->streaming;
    return proto_frame(PROTO_CONFIG, p, sizeof p, out);
}

size_t proto_frame_sample(const proto_sample_t *s, uint8_t *out)
{
    uint8_t p[PROTO_SAMPLE_LEN];
    proto_put_u16(p + 0, s->seq);
    proto_put_u32(p + 2, s->t_us);
    proto_put_u16(p + 6, (uint16_t)s->ax);
    proto_put_u16(p + 8, (uint16_t)s->ay);
    proto_put_u16(p + 10, (uint16_t)s->az);
    proto_put_u16(p + 12, (uint16_t)s->temp);
    proto_put_u16(p + 14, (uint16_t)s->gx);
    proto_put_u16(p + 16, (uint16_t)s->gy);
    proto_put_u16(p + 18, (uint16_t)s->gz);
    return proto_frame(PROTO_SAMPLE, p, sizeof p, out);
}

size_t proto_frame_ack(uint8_t command, uint8_t status, uint8_t *out)
{
    uint8_t p[PROTO_ACK_LEN] = {command, status};
    return proto_frame(PROTO_ACK, p, sizeof p, out);
}

void proto_parse_config(const uint8_t *p, proto_config_t *c)
{
    c->proto_version = p[0];
    c->fw_major = p[1];
    c->fw_minor = p[2];
    c->fw_patch = p[3];
    c->board = p[4];
    c->rate_hz = proto_get_u16(p + 5);
    c->accel_fs_g = p[7];
    c->gyro_fs_dps = proto_get_u16(p + 8);
    c->dlpf_cfg = p[10];
    c->streaming = p[11];
}

void proto_parse_sample(const uint8_t *p, proto_sample_t *s)
{
    s->seq = proto_get_u16(p + 0);
    s->t_us = proto_get_u32(p + 2);
    s->ax = proto_get_i16(p + 6);
    s->ay = proto_get_i16(p + 8);
    s->az = proto_get_i16(p + 10);
    s->temp = proto_get_i16(p + 12);
    s->gx = proto_get_i16(p + 14);
    s->gy = proto_get_i16(p + 16);
    s->gz = proto_get_i16(p + 18);
}

int proto_payload_len(uint8_t type)
{
    switch (type) {
    case PROTO_CONFIG:
        return PROTO_CONFIG_LEN;
    case PROTO_SAMPLE:
        return PROTO_SAMPLE_LEN;
    case PROTO_ACK:
        return PROTO_ACK_LEN;
    case PROTO_REQUEST_CONFIG:
    case PROTO_START:
    case PROTO_STOP:
        return 0;
    case PROTO_SET_RATE:
        return PROTO_SET_RATE_LEN;
    case PROTO_SET_RANGES:
        return PROTO_SET_RANGES_LEN;
    case PROTO_SET_DIALS:
        return PROTO_SET_DIALS_LEN;
    default:
        return -1;
    }
}

void proto_rx_init(proto_rx_t *rx)
{
    memset(rx, 0, sizeof *rx);
}

static int rx_bad(proto_rx_t *rx, uint8_t reason)
{
    rx->bad_reason = reason;
    rx->bad++;
    return PROTO_RX_BAD;
}

int proto_rx_push(proto_rx_t *rx, uint8_t byte)
{
    if (byte != 0x00) {
        if (rx->nraw < PROTO_MAX_WIRE - 1u)
            rx->raw[rx->nraw++] = byte;
        else
            rx->overflow = 1;
        return PROTO_RX_NONE;
    }
    /* A delimiter ends the frame, good or bad; the next byte starts anew. */
    uint8_t n = rx->nraw, over = rx->overflow;
    rx->nraw = 0;
    rx->overflow = 0;
    rx->type = 0;
    rx->plen = 0;
    rx->bad_reason = PROTO_BAD_NONE;
    if (n == 0 && !over)
        return PROTO_RX_EMPTY;
    if (over)
        return rx_bad(rx, PROTO_BAD_OVERLONG);
    int len = proto_cobs_decode(rx->raw, n, rx->body, sizeof rx->body);
    if (len < 0)
        return rx_bad(rx, PROTO_BAD_COBS);
    if (len < 3)
        return rx_bad(rx, PROTO_BAD_SHORT);
    rx->type = rx->body[0];
    uint16_t want = proto_get_u16(rx->body + len - 2);
    if (proto_crc16(rx->body, (size_t)len - 2) != want)
        return rx_bad(rx, PROTO_BAD_CRC);
    int plen = proto_payload_len(rx->type);
    if (plen < 0)
        return rx_bad(rx, PROTO_BAD_TYPE);
    if (plen != len - 3)
        return rx_bad(rx, PROTO_BAD_LENGTH);
    rx->plen = (uint8_t)plen;
    rx->frames++;
    return PROTO_RX_FRAME;
}
