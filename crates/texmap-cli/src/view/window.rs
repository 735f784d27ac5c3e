//! The viewer's event loop: input (every key press is queued by a callback, so a tap shorter
//! than a frame is not lost), the camera and settings it changes, the frames rendered in the
//! loop on the render's thread pool (the window stays responsive: while the camera moves a
//! frame is rendered at half size, and refined once it has been still for `SETTLE`), the
//! overlay, screenshots, and `--stats` at the end.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::{Duration, Instant};

use minifb::{InputCallback, Key, MouseButton, MouseMode, Window, WindowOptions};
use texmap::render::Frame;
use texmap::Error;

use super::camera::{ViewCamera, ORBIT_PER_KEY, ORBIT_PER_PX, ZOOM_STEP};
use super::look::{Look, Parts, PARTS};
use super::overlay::{text_width, Canvas, LINE};
use crate::formats::OutputFormat;
use crate::render::image_out::ImageOut;
use crate::render::{prepare, Common, Prepared, RenderArgs};

/// How long the camera must be still before a preview is refined.
const SETTLE: Duration = Duration::from_millis(150);
/// How near the divider (in pixels) a left press grabs it.
const GRAB: f32 = 6.0;

/// Key presses, in order, as the window reports them.
struct Presses(Rc<RefCell<Vec<Key>>>);

impl InputCallback for Presses {
    fn add_char(&mut self, _: u32) {}
    fn set_key_state(&mut self, key: Key, down: bool) {
        if down {
            self.0.borrow_mut().push(key);
        }
    }
}

/// One half of the A/B split (the whole window without it).
#[derive(Clone, Copy)]
struct Side {
    look: Look,
    parts: Parts,
}

/// The viewer's state.
struct Viewer<'a> {
    args: &'a RenderArgs,
    common: &'a Common,
    /// The command line's parts: the scene `texmap render` prepares.
    given: Parts,
    scenes: HashMap<Parts, Rc<Prepared>>,
    sides: [Side; 2],
    /// The A/B divider as a fraction of the width (none: no split).
    split: Option<f32>,
    camera: ViewCamera,
    /// Keys whose setting the scene does not have, with the reason.
    na: HashMap<char, String>,
    status: String,
    overlay: bool,
    help: bool,
    size: (u32, u32),
    stem: String,
    frames: [Frame; 2],
    /// The frames drawn are a preview (half size).
    preview_shown: bool,
    last_ms: f64,
    times: Vec<f64>,
    preview_times: Vec<f64>,
    last_shot: Option<PathBuf>,
    shots: u32,
}

/// Opens the window on `display` and runs until Escape or the window is closed.
pub fn run(args: &RenderArgs, common: &Common, display: &str, preview: bool) -> Result<(), Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let stem = crate::render::plan::stem(name);
    let given = Parts::of(args);
    let first = Rc::new(prepare(args, common)?);
    let subdivide = args.subdivide_error.unwrap_or(0.5);
    let look = Look::of(&first.settings, subdivide);
    let side = Side { look, parts: given };
    let bounds = bounds(&first);
    let mut viewer = Viewer {
        args,
        common,
        given,
        scenes: HashMap::from([(given, first.clone())]),
        sides: [side; 2],
        split: None,
        camera: ViewCamera::new(first.camera, bounds),
        na: not_applicable(args, &first, &stem),
        status: String::new(),
        overlay: true,
        help: false,
        size: args.size,
        stem: stem.clone(),
        frames: [Frame::default(), Frame::default()],
        preview_shown: false,
        last_ms: 0.0,
        times: Vec::new(),
        preview_times: Vec::new(),
        last_shot: None,
        shots: 0,
    };
    let (w, h) = (args.size.0 as usize, args.size.1 as usize);
    let mut window = Window::new(&format!("texmap - {stem}"), w, h, WindowOptions::default())
        .map_err(|e| Error::parameter(format!("view: cannot open a window on {display}: {e}")))?;
    window.set_target_fps(60);
    let presses = Rc::new(RefCell::new(Vec::new()));
    window.set_input_callback(Box::new(Presses(presses.clone())));
    let mut pixels = vec![0u32; w * h];
    let mut dirty = true;
    let mut refine = false;
    let mut last_move: Option<Instant> = None;
    let mut last_mouse: Option<(f32, f32)> = None;
    let mut was_down = false;
    let mut dragging_divider = false;
    while window.is_open() {
        let mut moved = false;
        let mut redraw = false;
        let mouse = window.get_mouse_pos(MouseMode::Discard);
        let keys: Vec<Key> = presses.borrow_mut().drain(..).collect();
        let active = viewer.side_at(mouse.map(|m| m.0));
        let mut quit = false;
        for key in keys {
            match key {
                Key::Escape => quit = true,
                Key::F12 => {
                    viewer.status = match viewer.screenshot() {
                        Ok(p) => format!("wrote {}", p.display()),
                        Err(e) => format!("screenshot failed: {e}"),
                    };
                    redraw = true;
                }
                Key::R | Key::Home => {
                    viewer.camera.reset();
                    moved = true;
                }
                Key::Left => viewer.camera.orbit(-ORBIT_PER_KEY, 0.0),
                Key::Right => viewer.camera.orbit(ORBIT_PER_KEY, 0.0),
                Key::Up => viewer.camera.orbit(0.0, ORBIT_PER_KEY),
                Key::Down => viewer.camera.orbit(0.0, -ORBIT_PER_KEY),
                Key::Equal | Key::NumPadPlus => viewer.camera.zoom(ZOOM_STEP),
                Key::Minus | Key::NumPadMinus => viewer.camera.zoom(1.0 / ZOOM_STEP),
                Key::O => {
                    viewer.overlay ^= true;
                    redraw = true;
                }
                Key::H => {
                    viewer.help ^= true;
                    redraw = true;
                }
                Key::B => {
                    viewer.split = match viewer.split {
                        Some(_) => None,
                        None => {
                            viewer.sides[1] = viewer.sides[0];
                            Some(0.5)
                        }
                    };
                    dirty = true;
                }
                other => {
                    if let Some(c) = key_char(other) {
                        dirty |= viewer.press(c, active);
                        redraw = true;
                    }
                }
            }
            if matches!(
                key,
                Key::Left
                    | Key::Right
                    | Key::Up
                    | Key::Down
                    | Key::Equal
                    | Key::NumPadPlus
                    | Key::Minus
                    | Key::NumPadMinus
            ) {
                moved = true;
            }
        }
        if quit {
            break;
        }
        // Mouse: drags orbit, pan or move the divider; the wheel zooms.
        let left = window.get_mouse_down(MouseButton::Left);
        let other =
            window.get_mouse_down(MouseButton::Right) || window.get_mouse_down(MouseButton::Middle);
        let shift = window.is_key_down(Key::LeftShift) || window.is_key_down(Key::RightShift);
        if left && !was_down {
            dragging_divider = match (viewer.split, mouse) {
                (Some(f), Some((x, _))) => (x - f * w as f32).abs() <= GRAB,
                _ => false,
            };
        }
        was_down = left;
        if let (Some((x, y)), Some((px, py))) = (mouse, last_mouse) {
            let (dx, dy) = (x - px, y - py);
            if (dx, dy) != (0.0, 0.0) {
                if left && dragging_divider {
                    viewer.split = Some((x / w as f32).clamp(0.0, 1.0));
                    dirty = true;
                } else if (left && shift) || other {
                    viewer.camera.pan(dx, dy, args.size.1);
                    moved = true;
                } else if left {
                    viewer.camera.orbit(-dx * ORBIT_PER_PX, dy * ORBIT_PER_PX);
                    moved = true;
                }
            }
        }
        last_mouse = mouse;
        if let Some((_, notches)) = window.get_scroll_wheel() {
            if notches != 0.0 {
                viewer.camera.zoom(ZOOM_STEP.powf(notches));
                moved = true;
            }
        }
        if moved {
            last_move = Some(Instant::now());
            dirty = true;
        }
        let moving = last_move.is_some_and(|t| t.elapsed() < SETTLE);
        if dirty || (refine && !moving) {
            let small = preview && moving && dirty;
            viewer.render(small)?;
            dirty = false;
            refine = small;
            redraw = true;
        }
        if redraw {
            viewer.draw(&mut pixels, mouse.map(|m| m.0));
            window
                .update_with_buffer(&pixels, w, h)
                .map_err(|e| Error::parameter(format!("view: {e}")))?;
        } else {
            window.update();
        }
    }
    if args.stats {
        viewer.print_stats()?;
    }
    Ok(())
}

/// The bounds near and far enclose after a move: the meshes' and volumes' (none when the
/// scene is an environment alone).
fn bounds(p: &Prepared) -> Option<(glam::Vec3, glam::Vec3)> {
    let mut b: Option<(glam::Vec3, glam::Vec3)> = None;
    let mut add = |lo: glam::Vec3, hi: glam::Vec3| {
        b = Some(b.map_or((lo, hi), |(a, c)| (a.min(lo), c.max(hi))));
    };
    if !p.scene.meshes.is_empty() {
        let (lo, hi) = p.scene.bounds();
        add(lo, hi);
    }
    for v in &p.volumes {
        let (lo, hi) = v.volume.world_bounds();
        add(lo, hi);
    }
    b
}

/// The keys of settings `p`'s scene (`name`) does not have, with the reason the overlay
/// shows.
fn not_applicable(args: &RenderArgs, p: &Prepared, name: &str) -> HashMap<char, String> {
    let mut na = HashMap::new();
    if p.scene.meshes.is_empty() || p.section.is_some() {
        for c in ['s', 'i', 'v', 'm'] {
            na.insert(c, format!("{name} has no meshes to draw"));
        }
    } else if args.unlit {
        na.insert('s', "--unlit: nothing is shaded".to_string());
    }
    if p.scene.texture_samplers().is_empty() && p.scene.environment.is_none() {
        na.insert('f', format!("{name} reads no image texture"));
    }
    if p.scene.environment.is_none() {
        na.insert('e', format!("{name} has no environment"));
    }
    na
}

/// The setting key of `key` (`f`, `s`, …, the digits), if it is one.
fn key_char(key: Key) -> Option<char> {
    Some(match key {
        Key::F => 'f',
        Key::S => 's',
        Key::I => 'i',
        Key::V => 'v',
        Key::M => 'm',
        Key::E => 'e',
        Key::Key0 | Key::NumPad0 => '0',
        Key::Key1 | Key::NumPad1 => '1',
        Key::Key2 | Key::NumPad2 => '2',
        Key::Key3 | Key::NumPad3 => '3',
        Key::Key4 | Key::NumPad4 => '4',
        Key::Key5 | Key::NumPad5 => '5',
        Key::Key6 | Key::NumPad6 => '6',
        Key::Key7 | Key::NumPad7 => '7',
        Key::Key8 | Key::NumPad8 => '8',
        Key::Key9 | Key::NumPad9 => '9',
        _ => return None,
    })
}

impl Viewer<'_> {
    /// The side under the pointer's `x` (A without a split or a pointer).
    fn side_at(&self, x: Option<f32>) -> usize {
        match (self.split, x) {
            (Some(f), Some(x)) if x >= f * self.size.0 as f32 => 1,
            _ => 0,
        }
    }

    /// A setting key pressed over side `s`: true when the frame changes.
    fn press(&mut self, c: char, s: usize) -> bool {
        if let Some(why) = self.na.get(&c) {
            self.status = format!("{c}: n/a: {why}");
            return false;
        }
        let side = &mut self.sides[s];
        match c {
            'f' => side.look.next_filter(),
            's' => side.look.next_shading(),
            'i' => side.look.next_interpolation(),
            'v' => side.look.next_visibility(),
            'm' => side.look.next_antialiasing(),
            _ => {
                let parts = match c {
                    'e' => {
                        let mut p = side.parts;
                        p.environment ^= true;
                        p
                    }
                    _ => match PARTS.iter().find(|(k, _, _)| *k == c) {
                        Some((_, part, _)) => side.parts.toggled(*part),
                        None => return false,
                    },
                };
                match self.scene(parts) {
                    Ok(_) => self.sides[s].parts = parts,
                    Err(e) => {
                        self.status = format!("{c}: n/a: {e}");
                        self.na.insert(c, e.to_string());
                        return false;
                    }
                }
            }
        }
        self.status.clear();
        true
    }

    /// The scene prepared with `parts`: the render's `prepare` with their flags (cached;
    /// scenes no side shows are dropped, the command line's kept).
    fn scene(&mut self, parts: Parts) -> Result<Rc<Prepared>, Error> {
        if let Some(p) = self.scenes.get(&parts) {
            return Ok(p.clone());
        }
        let mut args = parts.apply(&self.given, self.args);
        args.quiet = true;
        let mut p = prepare(&args, self.common)?;
        if !parts.environment {
            p.scene.environment = None;
        }
        let used = [self.sides[0].parts, self.sides[1].parts, self.given];
        self.scenes.retain(|k, _| used.contains(k));
        let p = Rc::new(p);
        self.scenes.insert(parts, p.clone());
        Ok(p)
    }

    /// Renders the shown sides (half size for a preview) into `self.frames`.
    fn render(&mut self, preview: bool) -> Result<(), Error> {
        let (w, h) = if preview {
            ((self.size.0 / 2).max(1), (self.size.1 / 2).max(1))
        } else {
            self.size
        };
        let start = Instant::now();
        let count = if self.split.is_some() { 2 } else { 1 };
        for i in 0..count {
            let side = self.sides[i];
            let p = self.scene(side.parts)?;
            let settings = side.look.apply(&p.settings).with_size(w, h);
            let cam = self.camera.current();
            let frame = &mut self.frames[i];
            p.render_view(&self.common.pool, &p.volumes, &cam, &settings, frame)?;
        }
        let ms = start.elapsed().as_secs_f64() * 1e3;
        if preview {
            self.preview_times.push(ms);
        } else {
            self.times.push(ms);
        }
        self.last_ms = ms;
        self.preview_shown = preview;
        Ok(())
    }

    /// The divider's column (the width without a split).
    fn divider(&self) -> usize {
        let w = self.size.0 as usize;
        self.split
            .map_or(w, |f| ((f * w as f32).round() as usize).min(w))
    }

    /// The frames, divider, labels and overlay into `pixels`.
    fn draw(&self, pixels: &mut [u32], mouse_x: Option<f32>) {
        let (w, h) = (self.size.0 as usize, self.size.1 as usize);
        let mut canvas = Canvas {
            pixels,
            width: w,
            height: h,
        };
        let div = self.divider();
        canvas.blit(&self.frames[0], 0, div);
        if self.split.is_some() {
            canvas.blit(&self.frames[1], div, w);
            canvas.divider(div.min(w.saturating_sub(2)));
            for (i, (x0, x1)) in [(0, div), (div, w)].into_iter().enumerate() {
                let label = format!(
                    "{}: {}",
                    ["A", "B"][i],
                    self.sides[i].look.describe().map(|(_, v)| v).join(" ")
                );
                let room = (x1.saturating_sub(x0) / 8).saturating_sub(2);
                let label: String = label.chars().take(room).collect();
                canvas.text(x0 + 2, h.saturating_sub(LINE + 2), &[label]);
            }
        }
        if !self.overlay {
            return;
        }
        let active = self.side_at(mouse_x);
        let mut lines = vec![format!(
            "texmap {}  {}x{}  {:.1} ms/frame{}",
            self.stem,
            self.size.0,
            self.size.1,
            self.last_ms,
            if self.preview_shown {
                " (preview 1/2)"
            } else {
                ""
            }
        )];
        let sides = if self.split.is_some() { 2 } else { 1 };
        for (i, side) in self.sides.iter().enumerate().take(sides) {
            let keys = ['f', 's', 'i', 'v', 'm'];
            let words: Vec<String> = side
                .look
                .describe()
                .iter()
                .zip(keys)
                .map(|((name, v), k)| match self.na.contains_key(&k) {
                    true => format!("{name} n/a"),
                    false => format!("{name} {v}"),
                })
                .collect();
            let tag = if sides == 2 {
                format!("{}{} ", ["A", "B"][i], if i == active { "*" } else { "" })
            } else {
                String::new()
            };
            lines.push(format!("{tag}{}", words[..3].join("  ")));
            lines.push(format!("{tag}{}", words[3..].join("  ")));
        }
        let parts = self.sides[active].parts;
        let state = |c: char, on: bool| match self.na.contains_key(&c) {
            true => "n/a",
            false if on => "on",
            false => "off",
        };
        let mut words = vec![format!("e env {}", state('e', parts.environment))];
        words.extend(
            PARTS
                .iter()
                .map(|(c, part, name)| format!("{c} {name} {}", state(*c, parts.is_on(*part)))),
        );
        for chunk in words.chunks(4) {
            lines.push(chunk.join("  "));
        }
        if !self.status.is_empty() {
            lines.push(self.status.clone());
        }
        lines.push("h: keys  o: overlay".to_string());
        if self.help {
            lines.extend(super::KEYS.lines().map(str::to_string));
        }
        // Long lines are cut to the window.
        let room = w / 8;
        let lines: Vec<String> = lines
            .into_iter()
            .map(|l| {
                if text_width(&l) > w {
                    l.chars().take(room.saturating_sub(1)).collect()
                } else {
                    l
                }
            })
            .collect();
        canvas.text(2, 2, &lines);
    }

    /// Writes `texmap-SCENE-N.png` (the first N free) with the frame at full size, no
    /// overlay: `texmap render`'s image for the same view and settings (both halves with a
    /// split).
    fn screenshot(&mut self) -> Result<PathBuf, Error> {
        let count = if self.split.is_some() { 2 } else { 1 };
        let mut frames = [Frame::default(), Frame::default()];
        for (i, frame) in frames.iter_mut().enumerate().take(count) {
            let side = self.sides[i];
            let p = self.scene(side.parts)?;
            let settings = side.look.apply(&p.settings);
            let cam = self.camera.current();
            p.render_view(&self.common.pool, &p.volumes, &cam, &settings, frame)?;
        }
        let [mut shot, b] = frames;
        if count == 2 {
            let (w, div) = (shot.width as usize, self.divider());
            for (row_a, row_b) in shot.color.chunks_mut(w).zip(b.color.chunks(w)) {
                row_a[div..].copy_from_slice(&row_b[div..]);
            }
        }
        let path = loop {
            self.shots += 1;
            let p = PathBuf::from(format!("texmap-{}-{}.png", self.stem, self.shots));
            if std::fs::symlink_metadata(&p).is_err() {
                break p;
            }
        };
        ImageOut::new(self.args, OutputFormat::Png).write(&path, &shot)?;
        self.last_shot = Some(path.clone());
        Ok(path)
    }

    /// `--stats`: the render's JSON for the full-size frames drawn, and the previews'.
    fn print_stats(&mut self) -> Result<(), Error> {
        let p = self.scene(self.sides[0].parts)?;
        let output = self.last_shot.clone().unwrap_or_default();
        let mut json = p.stats(
            self.args,
            self.common,
            &self.times,
            &self.frames[0],
            Some(&output),
        );
        let (min, median, max) = crate::render::spread(&self.preview_times);
        let r = |v: f64| (v * 100.0).round() / 100.0;
        json["preview"] = serde_json::json!({
            "frames": self.preview_times.len(),
            "size": [(self.size.0 / 2).max(1), (self.size.1 / 2).max(1)],
            "frame_ms": {"min": r(min), "median": r(median), "max": r(max)},
        });
        crate::output::stdout(&format!("{json}\n"))
    }
}
