#!/usr/bin/env bash
# CI step for the Arduino firmware (issue 11): install Debian's AVR tool chain
# and simavr, build the firmware (nominal and simulated-unit calibration), run
# the host unit tests of its portable C and the simavr harness, decode the
# harness's captures with an independent decoder, print the figures. Exits non-zero on any failure. About a minute once apt is done.
set -euo pipefail
cd "$(dirname "$0")/../.."
start=$(date +%s)
say() { echo "-- avr: $* ($(( $(date +%s) - start )) s)"; }

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
PKGS="gcc-avr avr-libc binutils-avr arduino-core-avr simavr libsimavr-dev libelf-dev pkg-config gcc make python3"
say "apt-get install $PKGS"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q >/dev/null
$SUDO apt-get install -y -q --no-install-recommends $PKGS >/dev/null
avr-gcc --version | head -1

FW=firmware/arduino/clino_inclinometer
say "firmware, nominal calibration ($FW/build)"
make -s -C "$FW" CALIB=nominal
say "firmware, the simulated unit's calibration ($FW/build-sim)"
make -s -C "$FW" CALIB=sim

say "host unit tests (protocol, filter, calibration)"
make -s -C firmware/arduino/host_tests test

say "simavr harness"
make -s -C firmware/simavr harness
mkdir -p firmware/simavr/out
log=firmware/simavr/out/harness.log
set +e
firmware/simavr/harness "$FW/build-sim/clino_inclinometer.elf" firmware/simavr/out all | tee "$log"
rc=${PIPESTATUS[0]}
set -e

say "the captures through an independent decoder (Python, from the spec)"
set +e
python3 firmware/simavr/check_capture.py firmware/simavr/out
rc2=$?
set -e

say "figures"
avr-size "$FW/build/clino_inclinometer.elf" | sed 's/^/   /'
grep '^BENCH' "$log" | sed 's/^/   /' || true
ls -l firmware/simavr/out/*_capture.bin firmware/simavr/out/*_played.csv | sed 's/^/   /'
if [ "$rc" != 0 ] || [ "$rc2" != 0 ]; then
    echo "avr: the simavr harness (status $rc) or the capture check (status $rc2) failed" >&2
    exit 1
fi
say "done"
