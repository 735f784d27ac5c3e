//! `texmap view` as a user runs it: in a real X server (its own Xvfb on a free display,
//! driven by xdotool), F12's screenshot is `texmap render`'s image (PSNR ≥ 40 dB); `f`, `s`
//! and `1` change the next ones into the render's with those settings; Escape ends the
//! process with exit 0. Without a display it is one line and exit 1. Without Xvfb or xdotool installed the window test prints SKIPPED (CI
//! installs both: `.ci/run`).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Long enough for a slow, shared machine: these waits bound a hang, they time nothing.
const PATIENCE: Duration = Duration::from_secs(180);

fn texmap(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_texmap"));
    c.args(args);
    c
}

fn installed(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}

/// A child process killed when dropped (a failed assertion leaves no server or window).
struct Reaped(Child);

impl Drop for Reaped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts Xvfb on a display it picks free (`-displayfd`), returning it and its number.
fn xvfb() -> (Reaped, String) {
    let mut child = Command::new("Xvfb")
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "1280x800x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let number = line.trim().to_string();
    assert!(
        number.parse::<u32>().is_ok(),
        "Xvfb gave no display: {line:?}"
    );
    (Reaped(child), format!(":{number}"))
}

fn xdotool(display: &str, args: &[&str]) -> Output {
    Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .unwrap()
}

/// Waits for `done` to hold, checking every 100 ms, panicking with `what` after PATIENCE.
fn wait_for<T>(what: &str, mut done: impl FnMut() -> Option<T>) -> T {
    let start = Instant::now();
    loop {
        if let Some(v) = done() {
            return v;
        }
        assert!(start.elapsed() < PATIENCE, "gave up waiting for {what}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn psnr(a: &Path, b: &Path) -> f64 {
    let (a, b) = (
        image::open(a).unwrap().to_rgb8(),
        image::open(b).unwrap().to_rgb8(),
    );
    assert_eq!(a.dimensions(), b.dimensions());
    let (w, h) = a.dimensions();
    texmap::metrics::compare_rgb8(a.as_raw(), b.as_raw(), w as usize, h as usize, None).psnr_db
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_window_shows_the_renders_image_switches_techniques_and_quits_on_escape() {
    for program in ["Xvfb", "xdotool"] {
        if !installed(program) {
            eprintln!("SKIPPED: {program} is not installed (apt-get install xvfb xdotool)");
            return;
        }
    }
    let dir = scratch("viewer-window");
    // `texmap render` with the settings the keys below reach: none; `f` (the first filter
    // after each texture's own) and `s` (Phong to flat); `s` twice more (back to Phong)
    // and `1` (shadows off).
    let render = |name: &str, flags: &[&str]| {
        let path = dir.join(name);
        let r = texmap(&["render", "builtin:demo", "--size", "640x360", "--quiet"])
            .args(flags)
            .arg("-o")
            .arg(&path)
            .output()
            .unwrap();
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        path
    };
    let reference = render("reference.png", &[]);
    let flat = render("flat.png", &["--filter", "nearest", "--shading", "flat"]);
    let nearest = render("nearest.png", &["--filter", "nearest"]);
    let unshadowed = render(
        "unshadowed.png",
        &["--filter", "nearest", "--shadows=false"],
    );

    let (_server, display) = xvfb();
    let mut view = Reaped(
        texmap(&["view", "builtin:demo", "--size", "640x360", "--stats"])
            .current_dir(&dir)
            .env("DISPLAY", &display)
            .env_remove("WAYLAND_DISPLAY")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // The window, once mapped, takes the keyboard focus: xdotool's keys (XTEST) go to it.
    wait_for("the window to take the focus", || {
        if let Ok(Some(status)) = view.0.try_wait() {
            panic!("texmap view ended before its window opened: {status}");
        }
        let found = xdotool(&display, &["search", "--name", "^texmap - demo$"]);
        let id = String::from_utf8_lossy(&found.stdout)
            .lines()
            .next()?
            .to_string();
        xdotool(&display, &["windowfocus", "--sync", &id])
            .status
            .success()
            .then_some(())
    });
    let key = |k: &str| {
        let r = xdotool(&display, &["key", "--delay", "50", k]);
        assert!(r.status.success(), "xdotool key {k}");
    };
    let shot = |n: u32| {
        let path = dir.join(format!("texmap-demo-{n}.png"));
        wait_for(&format!("screenshot {n}"), || path.is_file().then_some(()));
        path
    };

    key("F12");
    let first = shot(1);
    let same = psnr(&reference, &first);
    assert!(
        same >= 40.0,
        "F12's screenshot vs render: PSNR {same:.2} dB"
    );

    key("f");
    key("s");
    key("F12");
    let second = shot(2);
    let changed = psnr(&reference, &second);
    assert!(
        changed < 40.0,
        "f and s changed nothing: PSNR {changed:.2} dB"
    );
    let same = psnr(&flat, &second);
    assert!(same >= 40.0, "after f and s vs render: PSNR {same:.2} dB");

    // A texture application's key prepares the scene again with the render's flag.
    key("s");
    key("s");
    key("1");
    key("F12");
    let third = shot(3);
    let changed = psnr(&nearest, &third);
    assert!(changed < 40.0, "1 changed nothing: PSNR {changed:.2} dB");
    let same = psnr(&unshadowed, &third);
    assert!(
        same >= 40.0,
        "after 1 vs render --shadows=false: PSNR {same:.2} dB"
    );

    key("Escape");
    let status = wait_for("the viewer to end after Escape", || {
        view.0.try_wait().unwrap()
    });
    let mut stderr = String::new();
    std::io::Read::read_to_string(view.0.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert!(status.success(), "exit {status}: {stderr}");
    // --stats: the render's JSON for the frames drawn.
    let mut stdout = String::new();
    std::io::Read::read_to_string(view.0.stdout.as_mut().unwrap(), &mut stdout).unwrap();
    let json: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(json["scene"], "builtin:demo");
    assert_eq!(json["size"], serde_json::json!([640, 360]));
    assert!(json["frames"].as_u64().unwrap() >= 1, "{json}");
    assert!(json["frame_ms"]["median"].as_f64().unwrap() > 0.0, "{json}");
}

#[test]
fn without_a_display_it_says_so_in_one_line_and_exits_1() {
    let r = texmap(&["view", "builtin:demo"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(err.contains("DISPLAY"), "{err}");
    assert!(r.stdout.is_empty());
}

#[test]
fn render_flags_that_write_files_or_batches_are_refused() {
    for args in [
        &["view", "builtin:demo", "-o", "x.png"][..],
        &["view", "builtin:demo", "--frames", "4"],
        &["view", "builtin:demo", "builtin:plane"],
        &["view", "builtin:demo", "--discard"],
        &["view", "builtin:demo", "--manifest", "m.jsonl"],
    ] {
        let r = texmap(args).env("DISPLAY", ":9999").output().unwrap();
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        // Refused before any window is asked for.
        assert!(!err.contains("window"), "{args:?}: {err}");
    }
}
