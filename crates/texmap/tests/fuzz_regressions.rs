//! Replays every input a fuzzer found a fault with (`tests/fuzz_regressions/<target>/`,
//! one file per fault) through the fuzz harness: each must now load or fail cleanly.
//! New faults: reproduce with `cargo +nightly fuzz run <target> <file>` (see `fuzz/README.md`),
//! fix the cause, and commit the file here.

mod fuzz_harness;

use std::path::Path;

#[test]
fn every_recorded_fault_input_loads_or_fails_cleanly() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let mut replayed = 0;
    for (name, target) in fuzz_harness::TARGETS {
        let Ok(entries) = std::fs::read_dir(root.join(name)) else {
            continue;
        };
        let mut files: Vec<_> = entries.flatten().map(|e| e.path()).collect();
        files.sort();
        for f in files {
            let data = std::fs::read(&f).unwrap();
            eprintln!("{name}: {}", f.display());
            target(&data);
            replayed += 1;
        }
    }
    assert!(
        replayed > 0,
        "no regression inputs found under {}",
        root.display()
    );
}
