//! The page's browser side (wasm32 only): WebGPU's adapter and device requested
//! asynchronously with WebGPU's default limits, the frame loop, the controls of
//! `web/index.html`, the panels drawn on a 2D canvas, and the check (`?check=N`).
//!
//! The panels reach the screen through a readback and `putImageData` rather than a
//! WebGPU canvas: headless Chromium on SwiftShader, where the check runs, has no
//! presentable WebGPU canvas (configuring one loses the device), and the readback is the
//! same async path the check compares with.

use std::cell::{Cell, RefCell};
use std::rc::Rc;
use std::sync::Arc;

use wasm_bindgen::JsCast as _;
use wasm_bindgen::prelude::*;
use web_sys::{CanvasRenderingContext2d, Document, HtmlCanvasElement, HtmlInputElement};

use crate::check::{CheckReport, EqualQualityRun, equal_quality, run_check};
use crate::form;
use crate::graph::{Area, FrameTimes, SERIES};
use crate::metrics::psnr;
use crate::renderer::{
    BUDGET, Frame, Mode, PAGE_MAX_BUDGET, Reads, Renderer, TARGET_VARIANCE, page_settings,
};
use crate::scene::{View, params};

/// The controls a URL carries, by element id (each id is its parameter's name).
const URL_CONTROLS: [&str; 9] = [
    "side",
    "mode",
    "fixed",
    "sigma",
    "budget-min",
    "budget-max",
    "drag",
    "auto-orbit",
    "animate",
];

/// The page's default frame size; the panels are three frames side by side.
const SIZE: [u32; 2] = [320, 200];

/// Reference passes of the page's references (of `REFERENCE_RAYS` rays each).
const REFERENCE_PASSES: u32 = 16;

/// Frames per run of the equal-quality measurement.
const EQUAL_QUALITY_FRAMES: u32 = 24;

/// Frames the interactive page's frame-time graph holds (the check's holds all of its).
const GRAPH_FRAMES: usize = 120;

/// The frame-time graph's colours, by series (as [`SERIES`]).
const GRAPH_COLOURS: [&str; 2] = ["#ffb347", "#5ec8ff"];

thread_local! {
    /// When (`performance.now()`, ms after the page's navigation started) the module
    /// started, the WebGPU device was granted and the first frame was drawn: the page's
    /// first-run time.
    static MILESTONES: Cell<[Option<f64>; 3]> = const { Cell::new([None; 3]) };
}

/// Records milestone `i` ([`MILESTONES`]) the first time it is reached.
fn milestone(i: usize) {
    MILESTONES.with(|m| {
        let mut v = m.get();
        if v[i].is_none() {
            v[i] = Some(crate::now_ms());
            m.set(v);
            if i == 2 {
                let at = |k: usize| v[k].map_or(String::from("?"), |t| format!("{t:.0}"));
                // Not "SPVG-WEB ": that prefix is the check's verdict line.
                web_sys::console::log_1(
                    &format!(
                        "spvg-web: first frame shown {} ms after page load (performance.now() \
                         from navigation start; module started at {} ms, WebGPU device at {} ms)",
                        at(2),
                        at(0),
                        at(1)
                    )
                    .into(),
                );
            }
        }
    });
}

/// The first-frame time, once reached.
fn first_frame_ms() -> Option<f64> {
    MILESTONES.with(|m| m.get()[2])
}

/// What a failure of the page says: on the page, on the console and, in the check, as
/// the check's failing line.
#[derive(Clone, Debug)]
struct Page {
    document: Document,
    check: bool,
}

impl Page {
    fn element(&self, id: &str) -> Option<web_sys::Element> {
        self.document.get_element_by_id(id)
    }

    fn set_text(&self, id: &str, text: &str) {
        if let Some(e) = self.element(id) {
            e.set_text_content(Some(text));
        }
    }

    fn input(&self, id: &str) -> Option<HtmlInputElement> {
        self.element(id)?.dyn_into().ok()
    }

    fn select_value(&self, id: &str) -> String {
        self.element(id)
            .and_then(|e| e.dyn_into::<web_sys::HtmlSelectElement>().ok())
            .map(|s| s.value())
            .unwrap_or_default()
    }

    /// A control's value as its URL parameter carries it (a checkbox as `1` or `0`).
    fn control_value(&self, id: &str) -> Option<String> {
        let e = self.element(id)?;
        if let Ok(i) = e.clone().dyn_into::<HtmlInputElement>() {
            return Some(if i.type_() == "checkbox" {
                String::from(if i.checked() { "1" } else { "0" })
            } else {
                i.value()
            });
        }
        e.dyn_into::<web_sys::HtmlSelectElement>()
            .ok()
            .map(|s| s.value())
    }

    fn set_control(&self, id: &str, value: &str) {
        let Some(e) = self.element(id) else { return };
        if let Ok(i) = e.clone().dyn_into::<HtmlInputElement>() {
            if i.type_() == "checkbox" {
                i.set_checked(value == "1");
            } else {
                i.set_value(value);
            }
        } else if let Ok(s) = e.dyn_into::<web_sys::HtmlSelectElement>() {
            s.set_value(value);
        }
    }

    /// The page's query with every control's value set (other parameters, such as
    /// `size`, kept), so a view's settings can be shared as a URL.
    fn url_state(&self, query: &str) -> String {
        let Ok(q) = web_sys::UrlSearchParams::new_with_str(query) else {
            return String::new();
        };
        for id in URL_CONTROLS {
            if let Some(v) = self.control_value(id) {
                q.set(id, &v);
            }
        }
        String::from(q.to_string())
    }

    /// Sets the controls a query names (the rest keep their values).
    fn apply_url_state(&self, query: &str) {
        if let Ok(q) = web_sys::UrlSearchParams::new_with_str(query) {
            for id in URL_CONTROLS {
                if let Some(v) = q.get(id) {
                    self.set_control(id, &v);
                }
            }
        }
    }

    /// The check of the URL state: non-default values in every control, written to a
    /// query, the defaults restored, the query applied: every control must read its
    /// edited value again. The controls end as they began.
    fn url_round_trips(&self) -> Result<(), String> {
        let edited = [
            ("mode", "fixed"),
            ("fixed", "24"),
            ("sigma", "1e-3"),
            ("budget-min", "2"),
            ("budget-max", "128"),
            ("drag", "orbit"),
            ("auto-orbit", "1"),
            ("animate", "1"),
            ("side", "0"),
        ];
        let original = self.url_state("");
        for (id, v) in edited {
            self.set_control(id, v);
        }
        let shared = self.url_state("size=320x200");
        self.apply_url_state(&original);
        self.apply_url_state(&shared);
        let wrong: Vec<String> = edited
            .iter()
            .filter_map(|&(id, v)| {
                let got = self.control_value(id);
                (got.as_deref() != Some(v)).then(|| format!("{id}: {got:?} != {v}"))
            })
            .collect();
        self.apply_url_state(&original);
        if wrong.is_empty() && self.url_state("") == original {
            Ok(())
        } else {
            Err(format!(
                "the URL state did not round-trip ({}; query {shared})",
                wrong.join(", ")
            ))
        }
    }

    fn fail(&self, why: &str) {
        self.set_text("stats", "");
        self.set_text("status", why);
        web_sys::console::error_1(&why.into());
        if self.check {
            web_sys::console::log_1(&format!("SPVG-WEB FAIL {why}").into());
        }
    }
}

/// The module's entry point, called by `web/index.html` once the module is loaded, with
/// the adapter's name as the browser gives it (`GPUAdapterInfo`'s vendor, architecture,
/// device and description; wgpu's `AdapterInfo` has none of them on the web).
///
/// The page's URL may hold `check=N` (run the check over `N` frames and log its line),
/// `eq=K` (with the check, also measure the equal-quality figure over `K` frames per run)
/// and `size=WxH` (the frame size, default 320x200).
#[wasm_bindgen]
pub fn start(adapter: String) {
    let Some(document) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    let query = web_sys::window()
        .and_then(|w| w.location().search().ok())
        .unwrap_or_default();
    let query = web_sys::UrlSearchParams::new_with_str(&query).ok();
    let get = |k: &str| query.as_ref().and_then(|q| q.get(k));
    let check = get("check").map(|n| form::check_frames(&n));
    let equal_quality_frames = get("eq").map(|n| form::whole("?eq", &n, 1, 1000));
    let size = get("size").and_then(|s| {
        let (w, h) = s.split_once('x')?;
        Some([w.parse().ok()?, h.parse().ok()?])
    });
    milestone(0);
    let page = Page {
        document,
        check: check.is_some(),
    };
    let hook = page.clone();
    std::panic::set_hook(Box::new(move |info| {
        hook.fail(&format!("panic: {info}"));
    }));
    // A bad `?check=` or `?eq=` fails the check (a typo in CI must not pass).
    let (check, equal_quality_frames) = match (check.transpose(), equal_quality_frames.transpose())
    {
        (Ok(c), Ok(e)) => (c, e),
        (Err(why), _) | (_, Err(why)) => {
            page.fail(&format!(
                "{why} (the check needs ?check=N, N frames, and optionally &eq=K)"
            ));
            return;
        }
    };
    wasm_bindgen_futures::spawn_local(async move {
        let size = size.unwrap_or(SIZE).map(|n: u32| n.clamp(16, 2048));
        if let Err(why) = run(&page, &adapter, size, check, equal_quality_frames).await {
            page.fail(&why);
        }
    });
}

/// The adapter and device: WebGPU's default limits (what every browser grants), and
/// timestamp queries where the adapter offers them.
async fn device(page: &Page) -> Result<(wgpu::Device, wgpu::Queue), String> {
    let window = web_sys::window();
    // WebGPU exists only in a secure context (https, or http on localhost / 127.0.0.1):
    // over plain http on a LAN address navigator.gpu is missing for that reason, not for
    // the browser's.
    if window.as_ref().is_some_and(|w| !w.is_secure_context()) {
        return Err(NOT_SECURE.into());
    }
    let navigator = window.map(|w| w.navigator());
    let has_webgpu = navigator
        .as_ref()
        .is_some_and(|n| js_sys::Reflect::has(n, &"gpu".into()).unwrap_or(false));
    if !has_webgpu {
        return Err(NO_WEBGPU.into());
    }
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::BROWSER_WEBGPU,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions::default())
        .await
        .map_err(|e| format!("{NO_ADAPTER} ({e})"))?;
    let timestamps = adapter.features() & wgpu::Features::TIMESTAMP_QUERY;
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("spvg-web"),
            required_features: timestamps,
            required_limits: wgpu::Limits::default(),
            ..Default::default()
        })
        .await
        .map_err(|e| format!("the WebGPU adapter refused the device: {e}"))?;
    milestone(1);
    let errors = page.clone();
    device.on_uncaptured_error(Arc::new(move |e| {
        errors.fail(&format!("WebGPU error: {e}"));
    }));
    Ok((device, queue))
}

const NO_WEBGPU: &str = "This page needs WebGPU, and this browser does not offer it \
    (navigator.gpu is missing). Use a browser with WebGPU (Chrome or Edge 113 and later, \
    Safari 26, Firefox 141 on Windows), or start Chromium with --enable-unsafe-webgpu.";

const NOT_SECURE: &str = "This page needs WebGPU, which browsers offer only in a secure \
    context: open it over https, or over http on localhost or 127.0.0.1 (for example \
    `scripts/web-check.sh --serve` and http://127.0.0.1:8000/), not on a LAN address.";

const NO_ADAPTER: &str = "This browser offers WebGPU but no adapter for this page (the \
    GPU or its driver may be blocked; Chromium without a GPU needs \
    --enable-unsafe-webgpu --use-webgpu-adapter=swiftshader)";

/// Draws the three panels of `frame` on the canvas.
fn draw(canvas: &HtmlCanvasElement, frame: &Frame, size: [u32; 2]) -> Result<(), String> {
    draw_row(canvas, frame, size, 0)
}

/// Draws the three panels of `frame` as the canvas's row `row` (0 at the top; the
/// side-by-side's fixed frame is row 1).
fn draw_row(
    canvas: &HtmlCanvasElement,
    frame: &Frame,
    [w, h]: [u32; 2],
    row: u32,
) -> Result<(), String> {
    if frame.image.is_empty() {
        return Ok(());
    }
    let ctx: CanvasRenderingContext2d = canvas
        .get_context("2d")
        .ok()
        .flatten()
        .and_then(|c| c.dyn_into().ok())
        .ok_or("no 2D context on the canvas")?;
    let image = web_sys::ImageData::new_with_u8_clamped_array_and_sh(
        wasm_bindgen::Clamped(&frame.image),
        3 * w,
        h,
    )
    .map_err(|e| format!("ImageData: {e:?}"))?;
    ctx.put_image_data(&image, 0.0, f64::from(row * h))
        .map_err(|e| format!("putImageData: {e:?}"))?;
    milestone(2);
    Ok(())
}

/// Draws the frame-time graph on the canvas `#frame-times` and notes on it
/// (`data-points`, `adaptive,fixed`) the points it drew per series, which the check reads
/// back from the page. Returns those counts.
fn draw_frame_times(page: &Page, times: &FrameTimes) -> Result<[usize; 2], String> {
    let canvas: HtmlCanvasElement = page
        .element("frame-times")
        .and_then(|e| e.dyn_into().ok())
        .ok_or("the page has no canvas #frame-times")?;
    let ctx: CanvasRenderingContext2d = canvas
        .get_context("2d")
        .ok()
        .flatten()
        .and_then(|c| c.dyn_into().ok())
        .ok_or("no 2D context on the frame-time canvas")?;
    let (w, h) = (f64::from(canvas.width()), f64::from(canvas.height()));
    let area = Area {
        left: 62.0,
        top: 28.0,
        width: w - 74.0,
        height: h - 52.0,
    };
    let layout = times.layout(area);
    ctx.set_fill_style_str("#1d2029");
    ctx.fill_rect(0.0, 0.0, w, h);
    ctx.set_font("12px system-ui, sans-serif");
    ctx.set_line_width(1.0);
    // The y axis: time in ms, grid lines at its labels.
    ctx.set_text_align("right");
    ctx.set_text_baseline("middle");
    for &(ms, y) in &layout.ticks {
        ctx.set_stroke_style_str("#3a3f50");
        ctx.begin_path();
        ctx.move_to(area.left, y);
        ctx.line_to(area.left + area.width, y);
        ctx.stroke();
        ctx.set_fill_style_str("#aab");
        let _ = ctx.fill_text(&format!("{ms} ms"), area.left - 6.0, y);
    }
    // The x axis: the window's frames, the oldest held at the left.
    ctx.set_text_baseline("top");
    let below = area.top + area.height + 5.0;
    ctx.set_text_align("left");
    let _ = ctx.fill_text(&format!("frame {}", layout.span[0]), area.left, below);
    ctx.set_text_align("right");
    let right = area.left + area.width;
    let _ = ctx.fill_text(&format!("frame {}", layout.span[1]), right, below);
    ctx.set_text_align("center");
    let _ = ctx.fill_text(
        "frame (fixed step; the times do not drive the frames)",
        area.left + 0.5 * area.width,
        area.top + area.height + 5.0,
    );
    // The legend: what is measured, then each series.
    ctx.set_text_align("left");
    ctx.set_text_baseline("middle");
    ctx.set_fill_style_str("#dde");
    let title = "wall ms per frame, readback included:";
    let _ = ctx.fill_text(title, 8.0, 12.0);
    let mut x = 22.0 + ctx.measure_text(title).map_or(230.0, |m| m.width());
    for (s, name) in SERIES.iter().enumerate() {
        ctx.set_fill_style_str(GRAPH_COLOURS[s]);
        ctx.fill_rect(x, 8.0, 16.0, 8.0);
        ctx.set_fill_style_str("#dde");
        let label = format!("{name}, {} pts", times.points(s));
        let _ = ctx.fill_text(&label, x + 21.0, 12.0);
        x += 36.0 + ctx.measure_text(&label).map_or(120.0, |m| m.width());
    }
    let mut drawn = [0; 2];
    for (s, points) in layout.series.iter().enumerate() {
        ctx.set_stroke_style_str(GRAPH_COLOURS[s]);
        ctx.set_fill_style_str(GRAPH_COLOURS[s]);
        ctx.set_line_width(1.5);
        ctx.begin_path();
        for p in points {
            if p.joined {
                ctx.line_to(p.x, p.y);
            } else {
                ctx.move_to(p.x, p.y);
            }
        }
        ctx.stroke();
        for p in points {
            if p.clipped {
                // Above the scale: a triangle at the top edge and its time.
                ctx.begin_path();
                ctx.move_to(p.x, p.y - 4.0);
                ctx.line_to(p.x - 4.0, p.y + 3.0);
                ctx.line_to(p.x + 4.0, p.y + 3.0);
                ctx.close_path();
                ctx.fill();
                let _ = ctx.fill_text(
                    &format!("{:.0} ms", p.ms),
                    p.x + 6.0,
                    p.y + 6.0 + 12.0 * s as f64,
                );
            } else {
                ctx.fill_rect(p.x - 1.5, p.y - 1.5, 3.0, 3.0);
            }
            drawn[s] += 1;
        }
    }
    let _ = canvas.set_attribute("data-points", &format!("{},{}", drawn[0], drawn[1]));
    Ok(drawn)
}

/// The check of the frame-time graph: the page's `#frame-times` canvas says it drew one
/// point per frame of each series.
fn frame_time_points(page: &Page, frames: u32) -> Result<String, String> {
    let points = page
        .element("frame-times")
        .and_then(|e| e.get_attribute("data-points"))
        .ok_or("the frame-time graph is missing (no #frame-times with data-points)")?;
    let want = format!("{frames},{frames}");
    if points == want {
        Ok(format!(
            "frame_time_points=adaptive:{frames}/{frames},fixed:{frames}/{frames}"
        ))
    } else {
        Err(format!(
            "the frame-time graph drew {points} points (adaptive,fixed), want {want}: one per frame per series"
        ))
    }
}

/// Resolves on the browser's next animation frame.
async fn next_frame() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        if let Some(w) = web_sys::window() {
            let _ = w.request_animation_frame(&resolve);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}

async fn run(
    page: &Page,
    adapter: &str,
    size: [u32; 2],
    check: Option<u32>,
    equal_quality_frames: Option<u32>,
) -> Result<(), String> {
    let canvas: HtmlCanvasElement = page
        .element("panels")
        .and_then(|e| e.dyn_into().ok())
        .ok_or("the page has no canvas #panels")?;
    canvas.set_width(3 * size[0]);
    canvas.set_height(size[1]);
    page.set_text("status", "requesting a WebGPU device");
    page.set_text("heat-lo", "0 spp (black)");
    page.set_text(
        "err-hi",
        &format!("\u{2265} {} |error|", 1.0 / crate::renderer::ERROR_GAIN),
    );
    let (device, queue) = device(page).await?;
    let settings = page_settings(TARGET_VARIANCE, BUDGET).map_err(|e| e.to_string())?;
    let mut renderer = Renderer::new(&device, &queue, size, Mode::Adaptive, settings)
        .map_err(|e| e.to_string())?;
    let timing = if renderer.has_timestamps() {
        "timestamp queries"
    } else {
        "wall time"
    };
    page.set_text(
        "adapter",
        &format!(
            "{adapter}; WebGPU's default limits; {}x{} pixels; frame time: {timing}",
            size[0], size[1]
        ),
    );
    if let Some(frames) = check {
        page.set_text(
            "status",
            &format!("check: {frames} frames against the twin"),
        );
        let shown = canvas.clone();
        canvas.set_height(2 * size[1]);
        let _ = canvas.set_attribute("data-rows", "2");
        let mut side = Renderer::new(&device, &queue, size, Mode::Fixed(16), settings)
            .map_err(|e| e.to_string())?;
        // One point per frame of the path per series; the equal-quality runs after it
        // (row 0 again) are not on the graph.
        let frames = frames.max(1);
        let mut times = FrameTimes::new(frames as usize);
        let mut next = [0_u32; 2];
        let report = run_check(
            &mut renderer,
            Some(&mut side),
            frames,
            equal_quality_frames.unwrap_or(0),
            |row, f| {
                let _ = draw_row(&shown, f, size, row);
                let s = row.min(1) as usize;
                if next[s] < frames {
                    times.record(u64::from(next[s]), s, f.wall_ms);
                    next[s] += 1;
                    let _ = draw_frame_times(page, &times);
                }
            },
        )
        .await
        .map_err(|e| e.to_string())?;
        page.url_round_trips()?;
        let points = frame_time_points(page, frames)?;
        let first = first_frame_ms().map_or(String::from("?"), |t| format!("{t:.0}"));
        let line = format!(
            "{} url_state=round-trips {points} first_frame_ms={first} reference_ms={:.0} adapter=\"{adapter}\"",
            report.line(),
            report.reference_ms
        );
        page.set_text("stats", &check_summary(&report));
        page.set_text("status", &line);
        web_sys::console::log_1(&line.into());
        return Ok(());
    }
    // The side by side's fixed half: the same view at the adaptive frame's mean count.
    let mut side = Renderer::new(&device, &queue, size, Mode::Fixed(16), settings)
        .map_err(|e| e.to_string())?;
    interactive(page, &canvas, &mut renderer, &mut side).await
}

/// The check's figures for the page's text box.
fn check_summary(r: &CheckReport) -> String {
    let mut s = format!(
        "check         {} of {} frames equal to the component's twin (counts, history texels)\n\
         mean spp      {:.2}\n\
         frame time    {:.1} ms wall{}\n\
         PSNR (TAA)    {:.2} dB on the last frame, against the converged reference",
        r.equal,
        r.frames,
        r.spp,
        r.wall_ms,
        r.gpu_ms
            .map_or(String::new(), |g| format!(", {g:.1} ms timestamp queries")),
        r.psnr_taa,
    );
    if let Some(q) = &r.equal_quality {
        s.push_str(&format!(
            "\nequal quality AS {:.1} spp at {:.2} dB = {}",
            q.spp,
            q.psnr,
            q.equal.describe(q.spp)
        ));
    }
    s
}

/// What the pointer and the buttons asked for since the last frame.
#[derive(Debug, Default)]
struct Input {
    /// The pointer's drag since the last frame, in frame pixels.
    drag: [f32; 2],
    /// Where the pointer is, in frame pixels (the object follows it).
    at: Option<[f32; 2]>,
    dragging: bool,
    reference: bool,
    measure: bool,
    home: bool,
}

/// The pointer's position in frame pixels: the canvas shows three panels of the frame,
/// scaled by CSS.
fn frame_position(canvas: &HtmlCanvasElement, e: &web_sys::PointerEvent) -> [f32; 2] {
    let rect = canvas.get_bounding_client_rect();
    let width = f64::from(canvas.width() / 3);
    let scale = 3.0 * width / rect.width().max(1.0);
    let rows: u32 = canvas
        .get_attribute("data-rows")
        .and_then(|r| r.parse().ok())
        .unwrap_or(1);
    let height = f64::from(canvas.height() / rows.max(1));
    let x = (f64::from(e.client_x()) - rect.left()) * scale;
    let y = (f64::from(e.client_y()) - rect.top()) * scale;
    [x.rem_euclid(width) as f32, y.rem_euclid(height) as f32]
}

fn listen<E: wasm_bindgen::convert::FromWasmAbi + 'static>(
    target: &web_sys::EventTarget,
    event: &str,
    f: impl FnMut(E) + 'static,
) {
    let c = Closure::<dyn FnMut(E)>::new(f);
    let _ = target.add_event_listener_with_callback(event, c.as_ref().unchecked_ref());
    // The listeners live as long as the page.
    c.forget();
}

fn wire(page: &Page, canvas: &HtmlCanvasElement, input: &Rc<RefCell<Input>>) {
    let (c, i) = (canvas.clone(), input.clone());
    listen(canvas, "pointerdown", move |e: web_sys::PointerEvent| {
        let mut i = i.borrow_mut();
        i.dragging = true;
        i.at = Some(frame_position(&c, &e));
        let _ = c.set_pointer_capture(e.pointer_id());
    });
    let (c, i) = (canvas.clone(), input.clone());
    listen(canvas, "pointermove", move |e: web_sys::PointerEvent| {
        let mut i = i.borrow_mut();
        if !i.dragging {
            return;
        }
        let p = frame_position(&c, &e);
        if let Some(a) = i.at {
            i.drag[0] += p[0] - a[0];
            i.drag[1] += p[1] - a[1];
        }
        i.at = Some(p);
    });
    for end in ["pointerup", "pointercancel"] {
        let i = input.clone();
        listen(canvas, end, move |_: web_sys::PointerEvent| {
            i.borrow_mut().dragging = false;
        });
    }
    for (id, set) in [
        (
            "reference",
            (|i: &mut Input| i.reference = true) as fn(&mut Input),
        ),
        ("measure", |i: &mut Input| i.measure = true),
        ("home", |i: &mut Input| i.home = true),
    ] {
        if let Some(button) = page.element(id) {
            let i = input.clone();
            listen(&button, "click", move |_: web_sys::Event| {
                set(&mut i.borrow_mut());
            });
        }
    }
}

/// The controls' values this frame.
#[derive(Clone, Debug, PartialEq)]
struct Controls {
    /// The count mode, or why the fixed count is refused.
    mode: Result<Mode, String>,
    /// `sigma0^2` and the budget as typed, or why they are refused.
    settings: Result<(f32, [u32; 2]), String>,
    drag: Drag,
    orbit: bool,
    animate: bool,
    /// Fixed against adaptive side by side (a second row of panels).
    side_by_side: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Drag {
    Pan,
    Orbit,
    Object,
}

fn controls(page: &Page) -> Controls {
    let text = |id: &str| page.input(id).map(|i| i.value()).unwrap_or_default();
    let checked = |id: &str| page.input(id).is_some_and(|i| i.checked());
    Controls {
        mode: if page.select_value("mode") == "fixed" {
            form::whole("fixed count", &text("fixed"), 1, PAGE_MAX_BUDGET).map(Mode::Fixed)
        } else {
            Ok(Mode::Adaptive)
        },
        settings: form::settings(&text("sigma"), &text("budget-min"), &text("budget-max")),
        drag: match page.select_value("drag").as_str() {
            "orbit" => Drag::Orbit,
            "object" => Drag::Object,
            _ => Drag::Pan,
        },
        orbit: checked("auto-orbit"),
        animate: checked("animate"),
        side_by_side: checked("side"),
    }
}

/// A running mean of the last frames' times.
fn smooth(old: Option<f64>, new: f64) -> f64 {
    old.map_or(new, |o| 0.9 * o + 0.1 * new)
}

async fn interactive(
    page: &Page,
    canvas: &HtmlCanvasElement,
    renderer: &mut Renderer,
    side: &mut Renderer,
) -> Result<(), String> {
    let input = Rc::new(RefCell::new(Input::default()));
    wire(page, canvas, &input);
    let window = web_sys::window().ok_or("no window")?;
    page.apply_url_state(&window.location().search().unwrap_or_default());
    let size = renderer.size();
    let [w, h] = size;
    let mut view = View::default();
    // What the renderer runs (the stats show these, never a refused value), and the
    // controls last seen: a change is judged once, when it is made.
    let mut live = (TARGET_VARIANCE, BUDGET);
    let mut seen = Controls {
        settings: Ok(live),
        mode: Ok(renderer.mode()),
        ..controls(page)
    };
    // Why the settings ([0]) and the fixed count ([1]) were refused, while they are.
    let mut refused: [Option<String>; 2] = [None, None];
    let mut reference: Option<(View, Vec<f32>)> = None;
    let mut measured: Option<(View, EqualQualityRun)> = None;
    let (mut wall, mut stamp): (Option<f64>, Option<f64>) = (None, None);
    let mut times = FrameTimes::new(GRAPH_FRAMES);
    let mut t = 0_u32;
    page.set_text("status", "running: drag on the panels");
    loop {
        let c = controls(page);
        if c.settings != seen.settings {
            let applied = c.settings.clone().and_then(|(v, b)| {
                let s = page_settings(v, b).map_err(|e| e.to_string())?;
                renderer.set_settings(s).map_err(|e| e.to_string())?;
                Ok((v, b))
            });
            refused[0] = applied.map(|s| live = s).err();
        }
        if c.mode != seen.mode {
            refused[1] = c.mode.clone().map(|m| renderer.set_mode(m)).err();
        }
        if c != seen {
            // The URL follows the controls, so the address bar shares this view's settings.
            let query = page.url_state(&window.location().search().unwrap_or_default());
            let _ = window
                .history()
                .map(|h| h.replace_state_with_url(&JsValue::NULL, "", Some(&format!("?{query}"))));
            let why: Vec<&str> = refused.iter().flatten().map(String::as_str).collect();
            page.set_text(
                "status",
                &if why.is_empty() {
                    "running".into()
                } else {
                    format!(
                        "refused: {}; the stats show what still runs",
                        why.join("; ")
                    )
                },
            );
            seen = c.clone();
        }
        let previous = view;
        let (requests, drag, at) = {
            let mut i = input.borrow_mut();
            let r = (i.reference, i.measure, i.home);
            (i.reference, i.measure, i.home) = (false, false, false);
            (r, std::mem::take(&mut i.drag), i.at.filter(|_| i.dragging))
        };
        match c.drag {
            Drag::Pan => view.pan(drag),
            Drag::Orbit => view.angle += 0.5 * drag[0],
            Drag::Object => {
                if let Some(p) = at {
                    view.object = view.world(size, p);
                }
            }
        }
        if c.orbit {
            view.angle += 0.5;
        }
        if c.animate {
            // An ellipse around the view's centre, 2 px per frame or so.
            let phase = t as f32 * 0.03;
            view.object = [
                view.centre[0] + 70.0 * phase.cos(),
                view.centre[1] + 45.0 * phase.sin(),
            ];
        }
        if requests.2 {
            view = View::default();
        }
        let (want_reference, want_measure) = (requests.0, requests.1);
        if want_reference || want_measure {
            page.set_text("status", "converging a reference of this view");
            let p = params(w, h, t, &view, &view);
            let r = renderer
                .converge_reference(&p, REFERENCE_PASSES)
                .await
                .map_err(|e| e.to_string())?;
            side.set_reference(&p, &r);
            reference = Some((view, r));
            page.set_text("status", "running");
        }
        if let (true, Some((v, r))) = (want_measure, &reference) {
            let running = renderer.mode();
            let shown = canvas.clone();
            let total = 5 * EQUAL_QUALITY_FRAMES;
            let mut done = 0;
            let button = page.element("measure");
            if let Some(b) = &button {
                b.set_text_content(Some("Cancel measuring"));
            }
            // A second click on the button (now "Cancel measuring") cancels between frames:
            // every frame awaits its readback, so the browser runs the click meanwhile.
            let run = equal_quality(renderer, v, EQUAL_QUALITY_FRAMES, r, |f| {
                let _ = draw(&shown, f, size);
                done += 1;
                let run = ["fixed 8", "fixed 16", "fixed 32", "fixed 64", "adaptive"]
                    [((done - 1) / EQUAL_QUALITY_FRAMES).min(4) as usize];
                page.set_text(
                    "status",
                    &format!(
                        "measuring equal quality on this view: frame {done} of {total} ({run}); \
                         click \"Cancel measuring\" to stop"
                    ),
                );
                !std::mem::take(&mut input.borrow_mut().measure)
            })
            .await
            .map_err(|e| e.to_string())?;
            if let Some(b) = &button {
                b.set_text_content(Some("Measure equal quality"));
            }
            renderer.set_mode(running);
            renderer.reset();
            match run {
                Some(run) => {
                    measured = Some((*v, run));
                    page.set_text("status", "running");
                }
                None => page.set_text("status", "equal-quality measurement cancelled"),
            }
        }
        let p = params(w, h, t, &view, &previous);
        let on_reference = reference.as_ref().filter(|(v, _)| *v == view);
        let reads = Reads {
            image: true,
            taa: on_reference.is_some(),
            twin: false,
        };
        let frame = renderer
            .render(&p, reads)
            .await
            .map_err(|e| e.to_string())?;
        draw(canvas, &frame, size)?;
        let rows = 1 + u32::from(c.side_by_side);
        if canvas.height() != rows * h {
            canvas.set_height(rows * h);
            let _ = canvas.set_attribute("data-rows", &rows.to_string());
            draw(canvas, &frame, size)?;
        }
        // Fixed at the adaptive frame's mean count, same view, same frame seed.
        let fixed_side = if c.side_by_side {
            let n = (frame.mean_spp().round() as u32).clamp(1, PAGE_MAX_BUDGET);
            if side.mode() != Mode::Fixed(n) {
                side.set_mode(Mode::Fixed(n));
            }
            if requests.2 {
                side.reset();
            }
            let f = side.render(&p, reads).await.map_err(|e| e.to_string())?;
            draw_row(canvas, &f, size, 1)?;
            times.record(u64::from(t), 1, f.wall_ms);
            Some((n, on_reference.map(|(_, r)| psnr(&f.taa, r))))
        } else {
            None
        };
        times.record(u64::from(t), 0, frame.wall_ms);
        draw_frame_times(page, &times)?;
        let max = renderer.settings().config.max_samples();
        let scale = match renderer.mode() {
            Mode::Fixed(n) => n.max(max),
            Mode::Adaptive => max,
        };
        page.set_text("heat-hi", &format!("{scale} spp"));
        wall = Some(smooth(wall, frame.wall_ms));
        stamp = frame.gpu_ms.map(|g| smooth(stamp, g));
        let mode = match renderer.mode() {
            Mode::Fixed(n) => format!("fixed {n} spp"),
            Mode::Adaptive => format!(
                "adaptive (AS), sigma0^2 = {:e}, budget [{}, {}]",
                live.0, live.1[0], live.1[1]
            ),
        };
        let mode = if refused.iter().any(Option::is_some) {
            format!("{mode} (the refused values do not run)")
        } else {
            mode
        };
        let time = match stamp {
            Some(s) => format!(
                "{s:.1} ms (timestamp queries; wall {:.1} ms)",
                wall.unwrap_or(0.0)
            ),
            None => format!("{:.1} ms (wall time)", wall.unwrap_or(0.0)),
        };
        let quality = match (on_reference, fixed_side) {
            (Some((_, r)), Some((n, Some(fixed)))) => format!(
                "top {:.2} dB, bottom (fixed {n} spp) {fixed:.2} dB, against this view's reference",
                psnr(&frame.taa, r)
            ),
            (Some((_, r)), _) => format!(
                "{:.2} dB against this view's reference",
                psnr(&frame.taa, r)
            ),
            (None, _) => "no reference for this view (\"Converge reference\")".into(),
        };
        let equal = match &measured {
            Some((v, q)) => format!(
                "AS {:.1} spp at {:.2} dB = {}{}",
                q.spp,
                q.psnr,
                q.equal.describe(q.spp),
                if *v == view {
                    ""
                } else {
                    " (on an earlier view)"
                }
            ),
            None => "not measured (\"Measure equal quality\")".into(),
        };
        page.set_text(
            "stats",
            &format!(
                "mode          {mode}\nmean spp      {:.2}{}\nframe time    {time}\nPSNR (TAA)    {quality}\nequal quality {equal}",
                frame.mean_spp(),
                fixed_side.map_or(String::new(), |(n, _)| format!(
                    " (top); bottom row fixed {n} spp, the same view at the top's mean"
                )),
            ),
        );
        t += 1;
        next_frame().await;
    }
}
