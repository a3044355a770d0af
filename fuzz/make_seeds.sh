#!/usr/bin/env bash
# Writes the seed inputs of the fuzz targets into fuzz/corpus/<target>/ (issue 14): a few events
# in every format written by `neurotac convert`, the head of the shared DAVIS240C recording in
# every format (when ../shared/data/davis240 is present, or $NEUROTAC_SHARED_DATA/davis240), and
# every crash-like case of issues 5 and 14: headers and magics cut at several offsets, NUL and
# escape bytes, too many fields, timestamps AEDAT 2.0 cannot hold, lines without an end.
# For the spike-dataset reader (`dataset`, issue 29): small datasets in every form a command
# reads (JSON, binary version 2 with its checksum, version 1 without), written by `neurotac
# synth` and `neurotac export` or by hand, and every crash-like case: cut at several offsets,
# NaN/Infinity/1e999 times, huge and "negative" (all ones) counts and lengths, labels beyond the
# class limit, deep nesting, duplicate keys, wrong types. For the parameter-file reader
# (`sim_params`): `neurotac simulate params` (the defaults) and the same crash-like cases.
# For the saved-network and description readers (`saved_network`, `description`): the seeds
# neurotac-neurons' replay test writes (see the end).
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
for t in usb_decode aedat2 aedat3 aedat4 text any_format dataset sim_params; do mkdir -p "$c/$t"; done
convert() { "$bin" convert "$@" --force > /dev/null; }

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

# ---- Spike datasets (target `dataset`) ----
d="$c/dataset"
# `le N V`: V as N little-endian bytes (bash arithmetic is 64-bit, so -1 is all ones).
le() { local i; for ((i = 0; i < $1; i++)); do printf "\\x$(printf %02x $((($2 >> (8 * i)) & 255)))"; done; }
u64() { le 8 "$1"; }
# Spike times as f64 bits: 0.25, 0.5, NaN, +Infinity.
t025='\x00\x00\x00\x00\x00\x00\xd0\x3f' t05='\x00\x00\x00\x00\x00\x00\xe0\x3f'
tnan='\x00\x00\x00\x00\x00\x00\xf8\x7f' tinf='\x00\x00\x00\x00\x00\x00\xf0\x7f'
# `v1 OBSERVATIONS NAMES META BODY`: a version-1 file (no checksum) with these counts, the
# metadata JSON text and the rest (label flag, labels, observations) as printf escapes.
v1() { printf 'NTSPIKES\x01\x00\x00\x00'; u64 "$1"; u64 "$2"; u64 ${#3}; printf '%s' "$3"; printf "$4"; }
one_obs() { u64 2; u64 2; u64 0; printf "$t025$t05"; } # 2 channels: [0.25, 0.5], []
{ v1 1 0 '{}' '\x01'; u64 0; one_obs; } > "$d/labelled_v1.bin"
v1 0 0 '{}' '\x00' > "$d/empty_v1.bin"
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 1; u64 1; u64 1; printf 'a'; u64 18; printf '{"duration_s":0.5}\x01'; u64 0; one_obs; } > "$d/named_v1.bin"
"$bin" synth --output "$tmp/synth.json" --samples 4 --classes 2 --channels 3 --spikes-per-unit 2 --duration 0.5s > /dev/null
cp "$tmp/synth.json" "$d/synth.json"
"$bin" export "$d/synth.json" "$d/synth.bin" --force > /dev/null
# `to_v1 NAME`: NAME.bin as version 1 (NAME_v1.bin): the checksum dropped, the version set to 1.
to_v1() {
  local n=$(($(wc -c < "$d/$1.bin") - 4))
  { printf 'NTSPIKES\x01\x00\x00\x00'; head -c "$n" "$d/$1.bin" | tail -c +13; } > "$d/$1_v1.bin"
}
to_v1 synth
printf '{"labels":[1,0],"class_names":["smooth","5 mm"],"observations":[[[0,0,0.5],[],[2e-9]],[[],[1],[]]],"meta":{"duration_s":2,"rig":{"x":[1,-0.0,{"y":null}]},"unicode":"\\u00e9\\ud83d\\ude00"}}' > "$d/hand.json"
"$bin" export "$d/hand.json" "$d/hand.bin" --force > /dev/null
to_v1 hand
printf '{"observations":[[[0.1]]]}' > "$d/unlabelled.json"
printf '{"observations":[]}' > "$d/empty.json"
printf '{"observations":[[],[]],"labels":[0,0]}' > "$d/no_channels.json"
printf ' \n{ "meta" : {} , "observations" : [ [ [ 1 , 2 ] ] ] , "extra" : [ ] }\n' > "$d/spaces_and_extra_key.json"
# Cut at several offsets: inside the magic, the version, counts, names, metadata, times, checksum.
for n in 1 4 8 11 12 16 20 28 40 70 130 200; do head -c "$n" "$d/synth.bin" > "$d/synth_cut_$n.bin"; done
size=$(wc -c < "$d/synth.bin")
for k in 1 4 5 9; do head -c $((size - k)) "$d/synth.bin" > "$d/synth_cut_end_$k.bin"; done
for n in 1 10 50 100 200 300; do head -c "$n" "$d/synth.json" > "$d/synth_cut_$n.json"; done
# A flipped byte (checksum mismatch); versions 0, 3 and all ones; trailing bytes.
{ head -c 100 "$d/synth.bin"; printf '\xff'; tail -c +102 "$d/synth.bin"; } > "$d/flipped_byte.bin"
for v in 0 3 -1; do { printf 'NTSPIKES'; le 4 "$v"; tail -c +13 "$d/synth.bin"; } > "$d/version_$((v & 0xffffffff)).bin"; done
{ cat "$d/labelled_v1.bin"; printf '\x00'; } > "$d/trailing_byte_v1.bin"
# Huge and "negative" (all ones) counts and lengths.
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 $((1 << 62)); } > "$d/huge_observation_count_v1.bin"
v1 -1 0 '{}' '\x00' > "$d/minus_one_observations_v1.bin"
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 0; u64 -1; } > "$d/minus_one_names_v1.bin"
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 0; u64 1; u64 $((1 << 40)); printf 'a'; } > "$d/huge_name_length_v1.bin"
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 0; u64 0; u64 -1; printf '{}\x00'; } > "$d/minus_one_meta_length_v1.bin"
{ v1 1 0 '{}' '\x00'; u64 $((1 << 61)); } > "$d/huge_channel_count_v1.bin"
{ v1 1 0 '{}' '\x00'; u64 2; u64 -1; u64 1; printf "$t025"; } > "$d/spike_counts_overflow_v1.bin"
{ v1 1 0 '{}' '\x00'; u64 1; u64 $((1 << 59)); printf "$t025"; } > "$d/huge_spike_count_v1.bin"
{ v1 1 0 '{}' '\x01'; u64 -1; one_obs; } > "$d/label_all_ones_v1.bin"
{ v1 1 0 '{}' '\x01'; u64 $((1 << 32)); one_obs; } > "$d/label_2_32_v1.bin"
{ v1 1 0 '{}' '\x01'; u64 4000000000; one_obs; } > "$d/label_4e9_v1.bin"
{ v1 1 0 '{}' '\x02'; u64 0; one_obs; } > "$d/label_flag_2_v1.bin"
# Invalid times and shapes.
{ v1 1 0 '{}' '\x00'; u64 1; u64 2; printf "$t025$tnan"; } > "$d/nan_time_v1.bin"
{ v1 1 0 '{}' '\x00'; u64 1; u64 1; printf "$tinf"; } > "$d/infinite_time_v1.bin"
{ v1 1 0 '{}' '\x00'; u64 1; u64 2; printf "$t05$t025"; } > "$d/unsorted_v1.bin"
{ v1 2 0 '{}' '\x00'; u64 1; u64 0; u64 2; u64 0; u64 0; } > "$d/channel_counts_differ_v1.bin"
v1 0 0 '[1]' '\x00' > "$d/meta_not_object_v1.bin"
v1 0 0 '{"duration_s":-1}' '\x00' > "$d/negative_duration_v1.bin"
{ printf 'NTSPIKES\x01\x00\x00\x00'; u64 0; u64 1; u64 2; printf '\xc3\x28'; u64 2; printf '{}\x00'; } > "$d/name_not_utf8_v1.bin"
deep() { local i; for ((i = 0; i < $1; i++)); do printf '['; done; for ((i = 0; i < $1; i++)); do printf ']'; done; }
meta="{\"deep\":$(deep 200)}"
v1 0 0 "$meta" '\x00' > "$d/deep_meta_v1.bin"
# JSON: values JSON or f64 cannot hold, wrong types, duplicate keys, deep nesting, bad shapes.
# `each TEMPLATE PREFIX NAME=VALUE…`: one file PREFIX_NAME.json per VALUE put into TEMPLATE.
each() {
  local template=$1 prefix=$2 pair
  shift 2
  for pair in "$@"; do printf "$template" "${pair#*=}" > "$d/${prefix}_${pair%%=*}.json"; done
}
each '{"observations":[[[0.1,%s]]]}' time nan=NaN infinity=Infinity minus_infinity=-Infinity \
  overflow=1e999 minus_overflow=-1e999 string='"0.1"' null=null bool=true list='[0.1]' object='{}'

printf '{"observations":[[[0.5,0.1]]]}' > "$d/unsorted.json"
each '{"labels":[0,%s],"observations":[[[0.1]],[[0.2]]]}' label minus_one=-1 1e20=1e20 \
  2_32=4294967296 4e9=4000000000 1023=1023 1024=1024 fraction=0.5 string='"0"' null=null
printf '{"labels":[0],"observations":[[[0.1]],[[0.2]]]}' > "$d/label_count.json"
printf '{"labels":[0,2],"class_names":["a","b"],"observations":[[[0.1]],[[0.2]]]}' > "$d/label_without_name.json"
printf '{"class_names":["a",1],"observations":[]}' > "$d/class_name_number.json"
printf '{"observations":[[[0.1]],[[0.2],[]]]}' > "$d/channel_counts_differ.json"
printf '{"observations":[[[0.1]]],"observations":[[[0.2]]]}' > "$d/duplicate_observations.json"
printf '{"labels":[0],"labels":[0],"observations":[[[0.1]]]}' > "$d/duplicate_labels.json"
printf '{"meta":{"a":1,"a":2},"observations":[]}' > "$d/duplicate_meta_key.json"
printf '{"observations":{"0":[[0.1]]}}' > "$d/observations_object.json"
printf '{"observations":[[[[0.1]]]]}' > "$d/too_deep_observations.json"
printf '{"observations":[],"meta":{"deep":%s}}' "$(deep 200)" > "$d/deep_meta.json"
printf '{"observations":[],"meta":{"deep":%s}}' "$(deep 120)" > "$d/deep_meta_within_limit.json"
printf '{"observations":%s}' "$(deep 200)" > "$d/deep_observations.json"
each '{"observations":[],"meta":{"duration_s":%s}}' duration zero=0 negative=-1 overflow=1e999 \
  string='"1"' null=null
printf '{}' > "$d/no_observations.json"
printf '[]' > "$d/array.json"
: > "$d/empty_file.json"
printf '\xef\xbb\xbf{"observations":[]}' > "$d/bom.json"
printf '{"observations":[]} x' > "$d/trailing_text.json"
printf '{"observations":[[["\xff"]]]}' > "$d/not_utf8.json"
printf '{"observations":[[[0.1\n,\n  NaN]]]}' > "$d/nan_on_line_2.json"

# ---- Simulator parameter files (target `sim_params`) ----
p="$c/sim_params"
"$bin" simulate params > "$p/default.json"
def="$p/default.json"
# `field NAME VALUE FILE`: the default file with field NAME set to VALUE (its first occurrence).
field() { sed "0,/\"$1\": [^,]*\([,]\{0,1\}\)\$/s//\"$1\": $2\1/" "$def" > "$p/$3"; }
field threshold_on NaN nan.json
field speed_mm_s Infinity infinity.json
field lever_mm 1e999 overflow.json
field distance_mm 1e308 huge.json
field threshold_off -0.25 negative.json
field refractory_s -0.0 negative_zero.json
field speed_mm_s '"15"' string_for_number.json
field bulge null null_for_number.json
field per_slide_offsets 0 number_for_bool.json
field period_rule '"hex"' unknown_rule.json
field period_rule '"centre_to_centre"' centre_to_centre.json
field microslip_max_mm 0.001 microslip_max_below_min.json
field leak_rate_hz 999 noise_over_budget.json
grep -v '"refractory_s"' "$def" > "$p/missing_field.json"
sed '0,/"speed_mm_s": 15.0,/s//"speed_mm_s": 15.0,\n    "speed": 1.0,/' "$def" > "$p/unknown_field.json"
sed '0,/"speed_mm_s": 15.0,/s//"speed_mm_s": 150.0,\n    "speed_mm_s": 15.0,/' "$def" > "$p/duplicate_field.json"
# The group `pixel` twice, the second with another threshold.
awk '/^  "pixel": \{/ { inside = 1 } inside { block = block $0 "\n" } { print }
     inside && /^  \},?$/ { inside = 0; gsub(/"threshold_on": 0.2/, "\"threshold_on\": 0.3", block); printf "%s", block }' \
  "$def" > "$p/duplicate_group.json"
sed "0,/^{\$/s//{\"deep\": $(deep 200),/" "$def" > "$p/deep_nesting.json"
sed "0,/\"sources\": {/s//\"sources\": {\"deep\": $(deep 100),/" "$def" > "$p/deep_sources.json"
sed '0,/"calibrated": \[/s//"calibrated": [5, /' "$def" > "$p/calibrated_extra_entry.json"
for n in 1 2 100 1000 5000; do head -c "$n" "$def" > "$p/cut_$n.json"; done
head -c $(($(wc -c < "$def") - 3)) "$def" > "$p/cut_end.json"
printf '{}' > "$p/empty_object.json"
printf '[]' > "$p/array.json"
printf 'null' > "$p/null.json"
: > "$p/empty_file.json"
{ printf '\xef\xbb\xbf'; cat "$def"; } > "$p/bom.json"
{ cat "$def"; printf 'x'; } > "$p/trailing_text.json"
# ---- Saved networks and descriptions (targets `saved_network`, `description`) ----
# Written by a test of neurotac-neurons (a network of the built-in models saved and described,
# clock- and event-driven; bodies cut at several offsets; every crafted case that made loading
# validation: huge delays, sizes and steps, a population saved without its state, spikes of
# neurons that do not exist, NaN currents and traces, overflowing STDP, dt = 1e-300).
cargo test --release -q -p neurotac-neurons --test fuzz_corpus_replay -- --ignored write_the_named_seeds > /dev/null
echo "seeds written to $c/"
