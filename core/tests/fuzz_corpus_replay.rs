//! The committed corpus of the fuzz target `dataset` (`fuzz/corpus/dataset/`), replayed on
//! stable (no nightly, no cargo-fuzz) through the same checks as the fuzzer
//! (`neurotac_core::testing::fuzz::check_dataset_bytes`): every file reads as a spike dataset or
//! fails with a typed error — never a panic — and what reads keeps its promises (labels, class
//! limit, channels, sorted finite times) and converts to both forms and back; a binary file also
//! reads alike as version 1 and as version 2. The memory a file's reading allocates stays under a
//! budget set by its size, so no corrupt count or length sizes an allocation.
//!
//! The corpus holds the named seeds of `fuzz/make_seeds.sh` (datasets in every form, cut files,
//! NaN and 1e999 times, huge and all-ones counts, labels beyond the class limit, deep nesting,
//! duplicate keys, wrong types) and what the fuzzer found, minimised (`fuzz/README.md`).

use neurotac_core::testing::fuzz::{
    PeakAllocator, check_dataset_bytes, corpus, peak_since, reset_peak,
};

#[global_allocator]
static GLOBAL: PeakAllocator = PeakAllocator;

/// Fixed part of the memory budget of one file: the readers' own structures and the checks'
/// copies.
const BUDGET_FIXED_BYTES: usize = 1 << 20;

/// Memory budget per input byte: the dataset read, its copies in both forms and their
/// read-backs (an empty JSON channel `[]` of 3 bytes becomes an 8-byte offset in each).
const BUDGET_PER_INPUT_BYTE: usize = 64;

#[test]
fn every_dataset_corpus_file_reads_or_fails_typed_within_its_memory_budget() {
    let Some(files) = corpus("dataset") else {
        return;
    };
    assert!(!files.is_empty(), "empty corpus");
    let (mut read, mut total_bytes) = (0, 0);
    for (name, bytes) in &files {
        let start = reset_peak();
        let result = std::panic::catch_unwind(|| check_dataset_bytes(bytes).is_ok());
        let used = peak_since(start);
        match result {
            Ok(ok) => read += usize::from(ok),
            Err(_) => panic!("dataset/{name}: a check failed (message above)"),
        }
        let budget = BUDGET_FIXED_BYTES + BUDGET_PER_INPUT_BYTE * bytes.len();
        assert!(
            used <= budget,
            "dataset/{name}: {used} bytes allocated at the peak, budget {budget}"
        );
        total_bytes += bytes.len();
    }
    // The committed corpus stays small.
    assert!(total_bytes <= 1_000_000, "corpus of {total_bytes} bytes");
    // The same small dataset written by `neurotac synth` (JSON), `neurotac export` (binary) and
    // as a version-1 file reads alike in every form, and so does the hand-made one.
    for names in [
        ["synth.json", "synth.bin", "synth_v1.bin"],
        ["hand.json", "hand.bin", "hand_v1.bin"],
    ] {
        let [a, b, c] = names.map(|name| {
            let (_, bytes) = files.iter().find(|(n, _)| n == name).expect(name);
            check_dataset_bytes(bytes).unwrap_or_else(|e| panic!("dataset/{name}: {e}"))
        });
        assert!(a == b && b == c, "{names:?} differ");
    }
    eprintln!(
        "replayed {} dataset corpus files ({total_bytes} bytes), {read} of them valid datasets",
        files.len()
    );
}
