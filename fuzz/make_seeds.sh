#!/usr/bin/env bash
# Writes small seed inputs for the fuzz targets into fuzz/corpus/<target>/ (not committed):
# a few events in every format, written by `neurotac convert`, and the first 4 KiB of the shared
# USB word stream when ../shared/data/davis240 is present.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p neurotac-experiments
bin="${CARGO_TARGET_DIR:-target}/release/neurotac"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
printf 't,x,y,on\n0,118,38,1\n3,102,28,0\n3,5,179,1\n40000,239,0,0\n2147483700,7,9,1\n' > "$tmp/seed.csv"
for t in usb_decode aedat2 aedat3 aedat4 text any_format; do mkdir -p "fuzz/corpus/$t"; done
"$bin" convert "$tmp/seed.csv" "fuzz/corpus/aedat2/seed.aedat" > /dev/null
"$bin" convert "$tmp/seed.csv" "fuzz/corpus/aedat3/seed.aedat3" > /dev/null
for c in none lz4 zstd; do
  "$bin" convert "$tmp/seed.csv" "fuzz/corpus/aedat4/$c.aedat4" --compression "$c" > /dev/null
done
"$bin" convert "$tmp/seed.csv" "fuzz/corpus/text/seed.txt" > /dev/null
cp "$tmp/seed.csv" fuzz/corpus/text/seed.csv
cp fuzz/corpus/aedat2/* fuzz/corpus/aedat3/* fuzz/corpus/aedat4/* fuzz/corpus/text/* fuzz/corpus/any_format/
usb=../shared/data/davis240/pick_usb_words.bin
if [ -f "$usb" ]; then head -c 4096 "$usb" > fuzz/corpus/usb_decode/pick_head.bin; fi
printf '\x07\x01\x00\x05\x80\x07\x10\x0a\x30\x0b\x20\xff\x7f\x08\x00' > fuzz/corpus/usb_decode/specials.bin
echo "seeds written to fuzz/corpus/"
