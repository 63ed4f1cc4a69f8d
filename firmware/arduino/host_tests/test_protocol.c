/*
 * Host unit test of the firmware's protocol.c (gcc on the host): the spec's
 * CRC check value, COBS vectors from Cheshire & Baker's paper / the usual
 * published table, whole frames written out by hand from the spec (checked
 * with an independent script when this test was written), the receiver's
 * handling of every bad-frame kind the spec names, and random round trips.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "protocol.h"

static int fails, checks;
#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        checks++;                                                                                  \
        if (!(cond)) {                                                                             \
            fails++;                                                                               \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                                            \
            printf(__VA_ARGS__);                                                                   \
            printf("\n");                                                                          \
        }                                                                                          \
    } while (0)

static void cobs_vector(const char *name, const uint8_t *in, size_t n, const uint8_t *want,
                        size_t wn)
{
    uint8_t enc[300], dec[300];
    size_t e = proto_cobs_encode(in, n, enc);
    CHECK(e == wn && memcmp(enc, want, wn) == 0, "COBS encode %s: %zu bytes, want %zu", name, e,
          wn);
    for (size_t i = 0; i < e; i++)
        CHECK(enc[i] != 0, "COBS %s: zero in the encoding at %zu", name, i);
    int d = proto_cobs_decode(want, wn, dec, sizeof dec);
    CHECK(d == (int)n && memcmp(dec, in, n) == 0, "COBS decode %s: %d bytes, want %zu", name, d,
          n);
}

static void test_crc(void)
{
    const uint8_t *s = (const uint8_t *)"123456789";
    CHECK(proto_crc16(s, 9) == 0x29B1, "CRC-16/CCITT-FALSE check value 0x%04X", proto_crc16(s, 9));
    CHECK(proto_crc16(s, 0) == 0xFFFF, "CRC of nothing is the init value");
    uint16_t c = proto_crc16_update(0xFFFF, s, 4);
    CHECK(proto_crc16_update(c, s + 4, 5) == 0x29B1, "CRC in two pieces");
}

static void test_cobs(void)
{
    uint8_t big[300], want[300];
    {
        const uint8_t in[] = {0x00}, w[] = {0x01, 0x01};
        cobs_vector("00", in, 1, w, 2);
    }
    {
        const uint8_t in[] = {0x00, 0x00}, w[] = {0x01, 0x01, 0x01};
        cobs_vector("00 00", in, 2, w, 3);
    }
    {
        const uint8_t in[] = {0x00, 0x11, 0x00}, w[] = {0x01, 0x02, 0x11, 0x01};
        cobs_vector("00 11 00", in, 3, w, 4);
    }
    {
        const uint8_t in[] = {0x11, 0x22, 0x00, 0x33}, w[] = {0x03, 0x11, 0x22, 0x02, 0x33};
        cobs_vector("11 22 00 33", in, 4, w, 5);
    }
    {
        const uint8_t in[] = {0x11, 0x22, 0x33, 0x44}, w[] = {0x05, 0x11, 0x22, 0x33, 0x44};
        cobs_vector("11 22 33 44", in, 4, w, 5);
    }
    {
        const uint8_t in[] = {0x11, 0x00, 0x00, 0x00}, w[] = {0x02, 0x11, 0x01, 0x01, 0x01};
        cobs_vector("11 00 00 00", in, 4, w, 5);
    }
    /* 01..FE (254 bytes) -> FF 01..FE */
    for (int i = 0; i < 254; i++)
        big[i] = (uint8_t)(i + 1);
    want[0] = 0xFF;
    memcpy(want + 1, big, 254);
    cobs_vector("01..FE", big, 254, want, 255);
    /* 00 01..FE (255 bytes) -> 01 FF 01..FE */
    big[0] = 0;
    for (int i = 1; i < 255; i++)
        big[i] = (uint8_t)i;
    want[0] = 0x01;
    want[1] = 0xFF;
    memcpy(want + 2, big + 1, 254);
    cobs_vector("00 01..FE", big, 255, want, 256);
    /* 01..FF (255 bytes) -> FF 01..FE 02 FF */
    for (int i = 0; i < 255; i++)
        big[i] = (uint8_t)(i + 1);
    want[0] = 0xFF;
    memcpy(want + 1, big, 254);
    want[255] = 0x02;
    want[256] = 0xFF;
    cobs_vector("01..FF", big, 255, want, 257);
    /* 02..FF 00 (255 bytes) -> FF 02..FF 01 01 */
    for (int i = 0; i < 254; i++)
        big[i] = (uint8_t)(i + 2);
    big[254] = 0;
    want[0] = 0xFF;
    memcpy(want + 1, big, 254);
    want[255] = 0x01;
    want[256] = 0x01;
    cobs_vector("02..FF 00", big, 255, want, 257);
    /* 03..FF 00 01 (255 bytes) -> FE 03..FF 02 01 */
    for (int i = 0; i < 253; i++)
        big[i] = (uint8_t)(i + 3);
    big[253] = 0;
    big[254] = 1;
    want[0] = 0xFE;
    memcpy(want + 1, big, 253);
    want[254] = 0x02;
    want[255] = 0x01;
    cobs_vector("03..FF 00 01", big, 255, want, 256);

    uint8_t out[8];
    const uint8_t zero_inside[] = {0x03, 0x11, 0x00};
    CHECK(proto_cobs_decode(zero_inside, 3, out, sizeof out) < 0, "COBS: a zero inside is bad");
    const uint8_t truncated[] = {0x05, 0x11, 0x22};
    CHECK(proto_cobs_decode(truncated, 3, out, sizeof out) < 0, "COBS: a code past the end");
    const uint8_t toolong[] = {0x09, 1, 2, 3, 4, 5, 6, 7, 8};
    CHECK(proto_cobs_decode(toolong, 9, out, 4) < 0, "COBS: output larger than the buffer");
}

static int same_sample(const proto_sample_t *a, const proto_sample_t *b)
{
    return a->seq == b->seq && a->t_us == b->t_us && a->ax == b->ax && a->ay == b->ay &&
           a->az == b->az && a->temp == b->temp && a->gx == b->gx && a->gy == b->gy &&
           a->gz == b->gz;
}

static int same_config(const proto_config_t *a, const proto_config_t *b)
{
    return a->proto_version == b->proto_version && a->fw_major == b->fw_major &&
           a->fw_minor == b->fw_minor && a->fw_patch == b->fw_patch && a->board == b->board &&
           a->rate_hz == b->rate_hz && a->accel_fs_g == b->accel_fs_g &&
           a->gyro_fs_dps == b->gyro_fs_dps && a->dlpf_cfg == b->dlpf_cfg &&
           a->streaming == b->streaming;
}

static void test_frames(void)
{
    uint8_t f[PROTO_MAX_WIRE];
    /* ACK(START, ok): body 03 13 00 + CRC 0xC3EC little-endian */
    const uint8_t ack[] = {0x03, 0x03, 0x13, 0x03, 0xEC, 0xC3, 0x00};
    size_t n = proto_frame_ack(PROTO_START, 0, f);
    CHECK(n == sizeof ack && memcmp(f, ack, n) == 0, "ACK frame bytes");
    /* SAMPLE seq 0x0102, t_us 0x00030000, ax -1, ay 0, az 16384, temp -4400,
     * gx 7, gy -7, gz 0 */
    const uint8_t sample[] = {0x04, 0x02, 0x02, 0x01, 0x01, 0x02, 0x03, 0x03, 0xff,
                              0xff, 0x01, 0x01, 0x05, 0x40, 0xd0, 0xee, 0x07, 0x03,
                              0xf9, 0xff, 0x01, 0x03, 0x05, 0x50, 0x00};
    proto_sample_t s = {0x0102, 0x00030000, -1, 0, 16384, -4400, 7, -7, 0};
    n = proto_frame_sample(&s, f);
    CHECK(n == sizeof sample && memcmp(f, sample, n) == 0, "SAMPLE frame bytes (%zu)", n);
    CHECK(n <= 25, "a SAMPLE frame is at most 25 bytes on the wire (spec)");
    /* CONFIG v1 fw 0.1.0 UNO 100 Hz +-4 g +-500 dps DLPF 3 streaming */
    const uint8_t config[] = {0x03, 0x01, 0x01, 0x02, 0x01, 0x03, 0x01, 0x64, 0x08,
                              0x04, 0xf4, 0x01, 0x03, 0x01, 0xa8, 0x9a, 0x00};
    proto_config_t c = {1, 0, 1, 0, 1, 100, 4, 500, 3, 1};
    n = proto_frame_config(&c, f);
    CHECK(n == sizeof config && memcmp(f, config, n) == 0, "CONFIG frame bytes (%zu)", n);

    /* the receiver gives them back, after garbage, and parses them */
    proto_rx_t rx;
    proto_rx_init(&rx);
    const uint8_t garbage[] = {0x55, 0x13, 0xFF, 0x02};
    int r = 0;
    for (size_t i = 0; i < sizeof garbage; i++)
        CHECK(proto_rx_push(&rx, garbage[i]) == PROTO_RX_NONE, "garbage is pending");
    for (size_t i = 0; i < sizeof sample; i++)
        r = proto_rx_push(&rx, sample[i]);
    CHECK(r == PROTO_RX_BAD, "garbage glued to a frame is one bad frame (resync at 0x00)");
    for (size_t i = 0; i < sizeof sample; i++)
        r = proto_rx_push(&rx, sample[i]);
    CHECK(r == PROTO_RX_FRAME && rx.type == PROTO_SAMPLE && rx.plen == 20, "SAMPLE received");
    proto_sample_t q;
    proto_parse_sample(rx.body + 1, &q);
    CHECK(same_sample(&q, &s), "SAMPLE parsed back");
    for (size_t i = 0; i < sizeof config; i++)
        r = proto_rx_push(&rx, config[i]);
    proto_config_t cc;
    proto_parse_config(rx.body + 1, &cc);
    CHECK(r == PROTO_RX_FRAME && same_config(&cc, &c), "CONFIG parsed back");
    CHECK(proto_rx_push(&rx, 0) == PROTO_RX_EMPTY, "a lone delimiter is no frame");
    CHECK(rx.frames == 2 && rx.bad == 1, "counters: %u good, %u bad", rx.frames, rx.bad);
}

static int push_all(proto_rx_t *rx, const uint8_t *b, size_t n)
{
    int r = PROTO_RX_NONE;
    for (size_t i = 0; i < n; i++)
        r = proto_rx_push(rx, b[i]);
    return r;
}

static void test_bad_frames(void)
{
    proto_rx_t rx;
    proto_rx_init(&rx);
    uint8_t f[PROTO_MAX_WIRE + 8], body[PROTO_MAX_BODY + 8];
    size_t n;

    /* CRC mismatch: every single-bit flip of every non-code byte is caught */
    proto_sample_t s = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    n = proto_frame_sample(&s, f);
    int caught = 0, tried = 0;
    for (size_t i = 0; i + 1 < n; i++)
        for (int b = 0; b < 8; b++) {
            uint8_t g[PROTO_MAX_WIRE];
            memcpy(g, f, n);
            g[i] ^= (uint8_t)(1u << b);
            if (g[i] == 0)
                continue; /* that is a delimiter, not a flipped byte */
            tried++;
            proto_rx_init(&rx);
            caught += push_all(&rx, g, n) == PROTO_RX_BAD;
        }
    CHECK(caught == tried, "single-bit flips caught: %d of %d", caught, tried);

    /* shorter than 3 bytes */
    proto_rx_init(&rx);
    const uint8_t shortf[] = {0x03, 0x10, 0x20, 0x00};
    CHECK(push_all(&rx, shortf, 4) == PROTO_RX_BAD && rx.bad_reason == PROTO_BAD_SHORT,
          "a 2-byte body is bad");
    /* unknown type, good CRC */
    n = proto_frame(0x42, NULL, 0, f);
    CHECK(push_all(&rx, f, n) == PROTO_RX_BAD && rx.bad_reason == PROTO_BAD_TYPE &&
              rx.type == 0x42,
          "unknown type");
    /* known type, wrong length, good CRC */
    uint8_t p3[3] = {1, 2, 3};
    n = proto_frame(PROTO_SET_RATE, p3, 3, f);
    CHECK(push_all(&rx, f, n) == PROTO_RX_BAD && rx.bad_reason == PROTO_BAD_LENGTH,
          "SET_RATE with 3 payload bytes");
    /* overlong: 70 non-zero bytes */
    memset(body, 0x5A, 70);
    CHECK(push_all(&rx, body, 70) == PROTO_RX_NONE, "overlong pending");
    CHECK(proto_rx_push(&rx, 0) == PROTO_RX_BAD && rx.bad_reason == PROTO_BAD_OVERLONG,
          "overlong frame");
    /* and the receiver works again right after */
    n = proto_frame_ack(PROTO_STOP, 0, f);
    CHECK(push_all(&rx, f, n) == PROTO_RX_FRAME && rx.type == PROTO_ACK, "resync after bad");
    CHECK(proto_frame(0x01, body, PROTO_MAX_PAYLOAD + 1, f) == 0, "payload too long refused");
    n = proto_frame(0x01, body, PROTO_MAX_PAYLOAD, f);
    CHECK(n <= PROTO_MAX_WIRE, "a 64-byte body fits in %u wire bytes (%zu)", PROTO_MAX_WIRE, n);
}

static void test_round_trips(void)
{
    srand(7);
    proto_rx_t rx;
    proto_rx_init(&rx);
    int ok = 0;
    for (int k = 0; k < 20000; k++) {
        proto_sample_t s;
        uint8_t *b = (uint8_t *)&s;
        for (size_t i = 0; i < sizeof s; i++)
            b[i] = (uint8_t)(rand() % 4 == 0 ? 0 : rand());
        uint8_t f[PROTO_MAX_WIRE];
        size_t n = proto_frame_sample(&s, f);
        if (push_all(&rx, f, n) == PROTO_RX_FRAME) {
            proto_sample_t q;
            proto_parse_sample(rx.body + 1, &q);
            ok += same_sample(&q, &s);
        }
    }
    CHECK(ok == 20000, "20000 random SAMPLE round trips, %d exact", ok);
}

int main(void)
{
    test_crc();
    test_cobs();
    test_frames();
    test_bad_frames();
    test_round_trips();
    printf("test_protocol: %d checks, %d failed\n", checks, fails);
    return fails ? 1 : 0;
}
