#!/usr/bin/env bash
# Writes the seed inputs of the fuzz targets into fuzz/corpus/<target>/ (issue 14): a few events
# in every format written by `neurotac convert`, the head of the shared DAVIS240C recording in
# every format (when ../shared/data/davis240 is present, or $NEUROTAC_SHARED_DATA/davis240), and
# every crash-like case of issues 5 and 14: headers and magics cut at several offsets, NUL and
# escape bytes, too many fields, timestamps AEDAT 2.0 cannot hold, lines without an end.
# The committed corpus is these seeds plus what the fuzzers found, minimised with
# `cargo fuzz cmin` (fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p neurotac-cli
bin="${CARGO_TARGET_DIR:-target}/release/neurotac"
data="${NEUROTAC_SHARED_DATA:-../shared/data}/davis240"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
c=fuzz/corpus
for t in usb_decode aedat2 aedat3 aedat4 text any_format; do mkdir -p "$c/$t"; done
convert() { "$bin" convert "$@" > /dev/null; }

# A few events: top-left and bottom-right pixels, equal times, a step just under 2^31 µs.
printf 't,x,y,on\n0,118,38,1\n3,102,28,0\n3,5,179,1\n40000,239,0,0\n2147483700,7,9,1\n' > "$tmp/seed.csv"
convert "$tmp/seed.csv" "$c/aedat2/seed.aedat"
convert "$tmp/seed.csv" "$c/aedat3/seed.aedat3"
for z in none lz4 zstd; do convert "$tmp/seed.csv" "$c/aedat4/seed_$z.aedat4" --compression "$z"; done
convert "$tmp/seed.csv" "$c/text/seed.txt"
cp "$tmp/seed.csv" "$c/text/seed.csv"

# The head of the shared recording (200 events) in every format.
if [ -d "$data" ]; then
  head -c $((248 + 8 * 200)) "$data/pick.aedat" > "$c/aedat2/pick_head.aedat"
  head -n 201 "$data/pick_events.csv" > "$c/text/pick_head.csv"
  head -n 200 "$data/pick_events.txt" > "$c/text/pick_head.txt"
  convert "$c/text/pick_head.csv" "$c/aedat3/pick_head.aedat3"
  for z in none lz4 zstd; do convert "$c/text/pick_head.csv" "$c/aedat4/pick_head_$z.aedat4" --compression "$z"; done
  head -c 4096 "$data/pick_usb_words.bin" > "$c/usb_decode/pick_head.bin"
  # issue 14 item 3: pick.aedat cut inside its 248-byte header, and inside its magic.
  for n in 5 10 12 13 14 66 100 173 200 247 248 249; do head -c "$n" "$data/pick.aedat" > "$c/aedat2/pick_cut_$n.aedat"; done
fi
printf '\x07\x01\x00\x05\x80\x07\x10\x0a\x30\x0b\x20\xff\x7f\x08\x00' > "$c/usb_decode/specials.bin"

# Cut headers and magics of the other versions.
for n in 9 11 13 20 40; do head -c "$n" "$c/aedat3/seed.aedat3" > "$c/aedat3/cut_$n.aedat3"; done
for n in 9 11 13 16 30; do head -c "$n" "$c/aedat4/seed_lz4.aedat4" > "$c/aedat4/cut_$n.aedat4"; done
printf '#!AER-DAT3.0\r\n' > "$c/any_format/version_3.0.aedat"
printf '#!AER-DAT2.0\r\n# AEChip: eu.seebetter.ini.chips.davis.Davis346B\r\n# End of ASCII Header\r\n' > "$c/aedat2/davis346.aedat"
printf '#!AER-DAT2.0\r\n# no sentinel\r\n\x00\x00\x00\x00\x00\x00\x00\x05' > "$c/aedat2/no_sentinel.aedat"

# issue 14 item 12: NUL and escape bytes, too many fields, a long line, a line without an end.
printf 't,x,y,on\n1,2\x003,1\n' > "$c/text/nul.csv"
printf '0.1 1 2 1\n0.2 1 2\x1b[31m 1\n' > "$c/text/escape.txt"
printf 't,x,y,on\n1,2,3,1,5\n' > "$c/text/too_many_fields.csv"
{ printf 't,x,y,on\n1,2,3,1'; for _ in $(seq 300); do printf ',7'; done; printf '\n'; } > "$c/text/long_line.csv"
printf '0.000001 1 2 1\r\n\r\n0.000002  3 4 0\r\n0.000003 5 6 1' > "$c/text/crlf_no_end.txt"
# Timestamps AEDAT 2.0 cannot hold (first beyond ±2^31 µs, a step of 2^32 µs), negative times,
# times near the i64 limits, coordinates outside the sensor, backwards time.
printf 't,x,y,on\n4294967296000,1,2,1\n-5,3,4,0\n' > "$c/text/beyond_aedat2.csv"
printf 't,x,y,on\n0,1,2,1\n4294967296,3,4,0\n9223372036854775,5,6,1\n-922337203685477,7,8,0\n' > "$c/text/far_times.csv"
printf 't,x,y,on\n10,1,2,1\n5,1,2,0\n11,300,2,1\n12,2,180,0\n' > "$c/text/backwards_outside.csv"
printf '999999999999.999999 1 2 1\n-999999999999.9999995 3 4 0\n' > "$c/text/far_seconds.txt"

# The named seeds (fuzzer finds are named by their hash, without an extension) for detection too.
cp "$c"/aedat2/*.* "$c"/aedat3/*.* "$c"/aedat4/*.* "$c"/text/*.* "$c/any_format/"
echo "seeds written to $c/"
