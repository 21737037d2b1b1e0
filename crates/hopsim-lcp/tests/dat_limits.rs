//! The `.dat` reader is bounded: a header declaring a huge `n` over a few numbers, an `n`
//! beyond the dimension limit, an endless input (`/dev/zero`, `/dev/urandom`) or a file
//! above the size limit is an error naming the file, the count or the limit, and never
//! reserves memory for values the file does not hold.

use hopsim_lcp::dat::{
    parse_dat, parse_dat_with, read_dat_with, DatLimits, MAX_BYTES_ENV, MAX_DAT_BYTES,
    MAX_DAT_DIMENSION, MAX_DIMENSION_ENV,
};
use hopsim_lcp::DatError;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Largest single allocation request seen, bytes.
static LARGEST: AtomicUsize = AtomicUsize::new(0);
/// Tests measuring `LARGEST` run one at a time.
static MEASURE: Mutex<()> = Mutex::new(());

struct Largest;

// SAFETY: forwards to the system allocator, only recording the largest request.
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Largest = Largest;

/// The error of parsing `text`, and the largest allocation made meanwhile.
fn parse_error_and_largest_allocation(text: &str) -> (String, usize) {
    let _one = MEASURE.lock().unwrap_or_else(|e| e.into_inner());
    LARGEST.store(0, Ordering::Relaxed);
    let result = parse_dat(text, "big.dat");
    let largest = LARGEST.load(Ordering::Relaxed);
    let err = result.expect_err("a broken header must be an error");
    assert!(matches!(err, DatError::Format { .. }), "{err:?}");
    (err.to_string(), largest)
}

fn header(n: &str) -> String {
    format!("{n} 0 {n} {n} {n} {n} ")
}

#[test]
fn a_huge_declared_size_over_three_numbers_is_a_count_error_not_an_allocation() {
    for n in ["100000", "2147483648", "4294967296", "18446744073709551615"] {
        let (msg, largest) = parse_error_and_largest_allocation(&format!("{}1 2 3", header(n)));
        assert!(
            msg.starts_with(&format!("big.dat: problem size n = {n} needs ")),
            "{msg}"
        );
        assert!(msg.ends_with("after the header, found 3"), "{msg}");
        assert!(largest < 1 << 20, "n = {n}: allocated {largest} bytes");
    }
}

#[test]
fn a_size_within_the_limit_over_few_numbers_reserves_only_what_is_there() {
    // 10 000² entries would be 800 MB: the reader must find the count short first.
    let n = MAX_DAT_DIMENSION.to_string();
    let (msg, largest) = parse_error_and_largest_allocation(&format!("{}1 2 3", header(&n)));
    assert_eq!(msg, "big.dat: expected 100000000 matrix entries, found 3");
    assert!(largest < 1 << 20, "allocated {largest} bytes");
}

#[test]
fn sizes_that_are_not_integers_are_named() {
    for n in ["1e9", "2^31", "-3", "0x10"] {
        let (msg, _) = parse_error_and_largest_allocation(&format!("{}1 2 3", header(n)));
        assert_eq!(
            msg,
            format!("big.dat: token 1 '{n}' (problem size n) is not a non-negative integer")
        );
    }
}

#[test]
fn the_dimension_limit_is_named_with_how_to_raise_it() {
    let text = "3 0 3 3 3 3 1 0 0 0 1 0 0 0 1 -1 -1 -1";
    let tight = DatLimits {
        max_dimension: 2,
        ..DatLimits::default()
    };
    let msg = parse_dat_with(text, "x.dat", &tight)
        .unwrap_err()
        .to_string();
    assert!(
        msg.starts_with("x.dat: problem size n = 3 is above the limit of 2")
            && msg.contains(&format!("{MAX_DIMENSION_ENV}=3")),
        "{msg}"
    );
    // The default limit reads it, and a raised limit reads it too.
    assert_eq!(parse_dat(text, "x.dat").unwrap().n(), 3);
    let raised = DatLimits {
        max_dimension: 3,
        ..tight
    };
    assert_eq!(parse_dat_with(text, "x.dat", &raised).unwrap().n(), 3);
}

fn io_error(path: &Path, limits: &DatLimits) -> String {
    match read_dat_with(path, limits) {
        Err(e @ DatError::Io { .. }) => e.to_string(),
        other => panic!("{}: expected an I/O error, got {other:?}", path.display()),
    }
}

#[test]
fn endless_inputs_are_refused_at_once() {
    for dev in ["/dev/zero", "/dev/urandom"] {
        let path = Path::new(dev);
        if !path.exists() {
            continue;
        }
        let msg = io_error(path, &DatLimits::default());
        assert!(
            msg.starts_with(&format!(
                "{dev}: cannot read: not a text file (NUL byte at offset "
            )),
            "{msg}"
        );
    }
}

#[test]
fn a_file_above_the_size_limit_is_refused_unread() {
    // A sparse file: its size is above the limit, its blocks cost nothing.
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hopsim_lcp_huge.dat");
    let file = std::fs::File::create(&path).unwrap();
    file.set_len(MAX_DAT_BYTES + 1).unwrap();
    drop(file);
    let msg = io_error(&path, &DatLimits::default());
    std::fs::remove_file(&path).unwrap();
    assert!(
        msg.ends_with(&format!(
            "cannot read: the file is larger than the 64 MiB limit of .dat files (set \
             {MAX_BYTES_ENV} to raise it)"
        )),
        "{msg}"
    );
}

fn temp_file(name: &str, text: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_file_above_the_size_limit_is_refused_and_one_below_is_read() {
    let text = "2 0 2 2 2 2 2 1 1 2 -5 -6";
    let path = temp_file("hopsim_lcp_dat_limit.dat", text);
    let tight = DatLimits {
        max_bytes: 10,
        ..DatLimits::default()
    };
    let msg = io_error(&path, &tight);
    assert!(
        msg.ends_with(
            "cannot read: the file is larger than the 10 bytes limit of .dat files \
                       (set HOPSIM_LCP_MAX_BYTES to raise it)"
        ),
        "{msg}"
    );
    let exact = DatLimits {
        max_bytes: text.len() as u64,
        ..tight
    };
    assert_eq!(read_dat_with(&path, &exact).unwrap().n(), 2);
}

#[test]
fn binary_input_is_named_as_such() {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hopsim_lcp_binary.dat");
    std::fs::write(&path, [b'2', b' ', 0xff, 0xfe]).unwrap();
    let msg = io_error(&path, &DatLimits::default());
    assert!(
        msg.ends_with("not a text file (invalid UTF-8 at offset 2)"),
        "{msg}"
    );
}
