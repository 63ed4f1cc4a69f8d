#!/usr/bin/env bash
# The Cortex-M4F firmware (issue 11, item 2): builds firmware/cortex-m for
# thumbv7em-none-eabihf (the QEMU build and the STM32F411 board build), runs
# the firmware library's unit tests on the host, boots it in QEMU
# (MPS2 AN386, a Cortex-M4 with FPU) with semihosting over the embedded BROAD
# excerpt, and compares every result with the host's clino-core pipeline
# (bit for bit). Prints the instruction counts (the FIGURE lines; BENCHMARKS.md,
# "Cortex-M4F firmware under QEMU"). Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/../cortex-m"
start=$(date +%s)
say() { echo "-- cortex-m: $* ($(( $(date +%s) - start )) s)"; }

if ! command -v qemu-system-arm >/dev/null; then
    say "installing qemu-system-arm (Debian)"
    SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq qemu-system-arm >/dev/null
fi
qemu-system-arm --version | head -n 1
rustup target add thumbv7em-none-eabihf

HOST=$(rustc -vV | sed -n 's/^host: //p')
TD="${CARGO_TARGET_DIR:-target}"
case "$TD" in /*) ;; *) TD="$(pwd)/$TD" ;; esac
ELF="$TD/thumbv7em-none-eabihf/release/clino-fw-qemu"
CSV="$(pwd)/../../crates/clino/data/broad_07_excerpt.csv"

say "cargo fmt --check (firmware workspace)"
cargo fmt --all -- --check

say "firmware build (thumbv7em-none-eabihf, release)"
cargo build --release --locked
ls -l "$ELF"

say "board binding build (STM32F411, stm32f4xx-hal; not run: no such board in QEMU)"
cargo build --release --locked -p clino-fw-stm32f4

say "unit tests on the host (clino-fw with mock I2C and PWM; the CSV converter)"
cargo test --release --locked --target "$HOST" -p clino-fw -p clino-fw-check

say "host checker build"
cargo build --release --locked --target "$HOST" -p clino-fw-check

say "QEMU run (mps2-an386, -icount shift=0, semihosting)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(
    cd "$work"
    timeout 180 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic \
        -monitor none -serial none -icount shift=0 \
        -semihosting-config enable=on,target=native -kernel "$ELF"
) | tee "$work/qemu.log"
grep -q '^clino-fw OK' "$work/qemu.log" || { echo "the firmware did not finish OK" >&2; exit 1; }

say "compare with the host pipeline"
"$TD/$HOST/release/clino-fw-check" "$CSV" "$work/clino-fw-quats.bin" "$work/qemu.log"

say "figures (instructions under QEMU -icount; BENCHMARKS.md)"
grep '^FIGURE' "$work/qemu.log"
say "done"
