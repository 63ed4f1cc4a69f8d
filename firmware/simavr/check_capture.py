#!/usr/bin/env python3
"""Decode the simavr harness's serial captures with an independent decoder.

For each scenario in OUTDIR (default firmware/simavr/out) this reads
<name>_capture.bin (every byte the simulated board sent), splits it on 0x00,
COBS-decodes and CRC-checks every frame (CRC-16/CCITT-FALSE, written here
from the spec, not from the firmware's C), and checks that

  * no frame is bad,
  * the SAMPLE frames are the rows of <name>_played.csv in order, bit-exact,
    with at most one run of rows missing (the STOP..START window of the
    100 Hz run), and
  * <name>_decoded.csv (the harness's conversion to clino fuse's raw CSV)
    equals this decoder's own conversion with the scale of the CONFIG frame
    in force, to 1e-12 relative.

This is also the recipe for any other decoder (e.g. clino_core::protocol):
feed the .bin, compare with the .csv files. Exit status 1 on any mismatch.
"""
import csv
import math
import os
import struct
import sys


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def cobs_decode(enc):
    out, i = bytearray(), 0
    while i < len(enc):
        code = enc[i]
        i += 1
        if code == 0 or i + code - 1 > len(enc):
            return None
        out += enc[i:i + code - 1]
        i += code - 1
        if code != 0xFF and i < len(enc):
            out.append(0)
    return bytes(out)


LEN = {0x01: 12, 0x02: 20, 0x03: 2}
LSB_G = {2: 16384.0, 4: 8192.0, 8: 4096.0, 16: 2048.0}
LSB_DPS = {250: 131.0, 500: 65.5, 1000: 32.8, 2000: 16.4}


def frames(blob):
    for chunk in blob.split(b"\x00")[:-1]:
        if not chunk:
            continue
        body = cobs_decode(chunk)
        if body is None or len(body) < 3:
            yield None
            continue
        t, payload, crc = body[0], body[1:-2], struct.unpack("<H", body[-2:])[0]
        if crc16(body[:-2]) != crc or LEN.get(t) != len(payload):
            yield None
            continue
        yield t, payload


def check(outdir, name):
    problems = []
    with open(os.path.join(outdir, name + "_capture.bin"), "rb") as f:
        blob = f.read()
    with open(os.path.join(outdir, name + "_played.csv"), newline="") as f:
        played = [tuple(int(r[k]) for k in ("ax", "ay", "az", "temp", "gx", "gy", "gz"))
                  for r in csv.DictReader(f)]
    with open(os.path.join(outdir, name + "_decoded.csv"), newline="") as f:
        decoded_csv = [[float(x) for x in r] for r in list(csv.reader(f))[1:]]
    bad, samples, mine = 0, [], []
    lsb_a, lsb_g, wraps, last = 8192.0, 65.5, 0, None
    for fr in frames(blob):
        if fr is None:
            bad += 1
            continue
        t, p = fr
        if t == 0x01:
            (_v, _ma, _mi, _pa, _b, _rate, afs, gfs, _dl, _st) = struct.unpack("<BBBBBHBHBB", p)
            lsb_a, lsb_g = LSB_G[afs], LSB_DPS[gfs]
        elif t == 0x02:
            seq, t_us, ax, ay, az, temp, gx, gy, gz = struct.unpack("<HIhhhhhhh", p)
            samples.append((ax, ay, az, temp, gx, gy, gz))
            if last is not None and t_us < last:
                wraps += 1
            last = t_us
            kg, ka = math.pi / 180.0 / lsb_g, 9.80665 / lsb_a
            mine.append([(wraps * 2**32 + t_us) * 1e-6, gx * kg, gy * kg, gz * kg,
                         ax * ka, ay * ka, az * ka, temp / 340.0 + 36.53])
    if bad:
        problems.append("%d bad frames" % bad)
    # the samples are the played rows in order, with at most one run missing
    j, runs, missing = 0, 0, 0
    for s in samples:
        k = j
        while k < len(played) and played[k] != s:
            k += 1
        if k == len(played):
            problems.append("a decoded sample matches no played row")
            break
        if k > j:
            runs += 1
            missing += k - j
        j = k + 1
    tail = len(played) - j
    if runs > 1 or tail > 1:
        problems.append("%d runs of played rows missing, %d rows after the last frame" % (runs, tail))
    if len(mine) != len(decoded_csv):
        problems.append("decoded.csv has %d rows, this decoder %d" % (len(decoded_csv), len(mine)))
    else:
        worst = max((abs(a - b) / max(abs(b), 1e-300) for ra, rb in zip(decoded_csv, mine)
                     for a, b in zip(ra, rb) if b != 0), default=0.0)
        if worst > 1e-12:
            problems.append("decoded.csv differs by %.3g relative" % worst)
    print("%-9s %6d bytes, %5d SAMPLE frames = played rows in order (%d held back in %d run), "
          "%d bad: %s" % (name, len(blob), len(samples), missing, runs, bad,
                          "ok" if not problems else "; ".join(problems)))
    return not problems


def main():
    outdir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "out")
    names = sorted(f[:-len("_capture.bin")] for f in os.listdir(outdir) if f.endswith("_capture.bin"))
    names = [n for n in names if os.path.exists(os.path.join(outdir, n + "_played.csv"))]
    ok = all([check(outdir, n) for n in names]) and bool(names)
    print("check_capture: %s" % ("PASSED" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
