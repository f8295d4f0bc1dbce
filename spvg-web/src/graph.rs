//! The page's frame-time graph: per frame, the wall time of the adaptive run and of the
//! fixed-count side (the side by side's second renderer), laid out as two polylines on a
//! small chart. The layout is plain Rust, so the native tests hold it; `page` strokes it
//! on a 2D canvas.
//!
//! The times are recorded, never read back into the frames: the frames step by a fixed
//! step whatever they cost (the check's determinism depends on it).

use std::collections::VecDeque;

/// The series, in the order [`FrameTimes::record`] takes them.
pub const SERIES: [&str; 2] = ["adaptive (AS)", "fixed (side by side)"];

/// The frame times of the last frames, two series.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameTimes {
    capacity: usize,
    /// The index of the oldest frame held.
    first: u64,
    /// Per frame held, oldest first: each series' time in milliseconds, if it ran.
    frames: VecDeque<[Option<f64>; 2]>,
}

/// One point of a series on the chart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The frame's index (0 the first frame recorded).
    pub frame: u64,
    /// Its time in milliseconds.
    pub ms: f64,
    /// Its x on the chart, in canvas pixels.
    pub x: f64,
    /// Its y on the chart, in canvas pixels (down, as a canvas has it).
    pub y: f64,
    /// Above the chart's scale and drawn at its top edge (the first frame, which compiles
    /// the pipelines, usually is).
    pub clipped: bool,
    /// Whether the line runs to this point from the series' previous one (false after a
    /// frame the series did not run).
    pub joined: bool,
}

/// The chart's plot area in canvas pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Area {
    /// The left edge (frame 0 of the window).
    pub left: f64,
    /// The top edge (the scale's time).
    pub top: f64,
    /// The width (the window's last frame at `left + width`).
    pub width: f64,
    /// The height (0 ms at `top + height`).
    pub height: f64,
}

/// Where everything goes.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The time at the top of the plot area (a round number).
    pub scale_ms: f64,
    /// The y axis' labels: time and y.
    pub ticks: Vec<(f64, f64)>,
    /// Each series' points, oldest first.
    pub series: [Vec<Point>; 2],
    /// The frames at the x axis' left and right edges (the window's span, whether or not
    /// it is full yet).
    pub span: [u64; 2],
}

impl FrameTimes {
    /// Room for the last `capacity` frames (at least one).
    #[must_use]
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(1),
            first: 0,
            frames: VecDeque::new(),
        }
    }

    /// Records `ms` as series `series`'s time on frame `frame`: a frame after the last
    /// one held starts new frames (the series that did not run there have no point),
    /// and the oldest frames beyond the capacity are dropped. A frame older than those
    /// held, a series out of range or a time that is not finite and non-negative is not
    /// recorded.
    pub fn record(&mut self, frame: u64, series: usize, ms: f64) {
        if series >= SERIES.len() || !ms.is_finite() || ms < 0.0 || frame < self.first {
            return;
        }
        let capacity = self.capacity as u64;
        if self.frames.is_empty() {
            self.first = frame;
        } else if frame >= self.first + self.frames.len() as u64 + capacity {
            // Every frame held would roll out: start the window afresh rather than push
            // and drop the frames between one by one.
            self.frames.clear();
            self.first = frame + 1 - capacity;
        }
        while self.first + self.frames.len() as u64 <= frame {
            self.frames.push_back([None; 2]);
            if self.frames.len() > self.capacity {
                self.frames.pop_front();
                self.first += 1;
            }
        }
        if let Some(f) = frame
            .checked_sub(self.first)
            .and_then(|i| self.frames.get_mut(i as usize))
        {
            f[series] = Some(ms);
        }
    }

    /// Frames held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether no frame is held.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// The points series `series` has among the frames held.
    #[must_use]
    pub fn points(&self, series: usize) -> usize {
        self.frames
            .iter()
            .filter(|f| f.get(series).copied().flatten().is_some())
            .count()
    }

    /// The chart in `area`: the x axis spans the capacity (the oldest frame held at the
    /// left), the y axis 0 to a round number at or above the largest time of the frames
    /// after frame 0 (frame 0 compiles the pipelines and would flatten the rest; it is
    /// drawn clipped when above), or of frame 0 when it is all there is.
    #[must_use]
    pub fn layout(&self, area: Area) -> Layout {
        let times = |skip_first: bool| {
            self.frames
                .iter()
                .enumerate()
                .filter(move |&(i, _)| !(skip_first && self.first + i as u64 == 0))
                .flat_map(|(_, f)| f.iter().flatten().copied())
        };
        let largest = times(true)
            .reduce(f64::max)
            .or_else(|| times(false).reduce(f64::max))
            .unwrap_or(0.0);
        let scale_ms = round_up(largest);
        let y = |ms: f64| area.top + area.height * (1.0 - (ms / scale_ms).min(1.0));
        let step = area.width / (self.capacity.max(2) - 1) as f64;
        let series = [0, 1].map(|s| {
            let mut points: Vec<Point> = Vec::new();
            for (i, f) in self.frames.iter().enumerate() {
                let Some(ms) = f[s] else { continue };
                let frame = self.first + i as u64;
                points.push(Point {
                    frame,
                    ms,
                    x: area.left + step * i as f64,
                    y: y(ms),
                    clipped: ms > scale_ms,
                    joined: points.last().is_some_and(|p| p.frame + 1 == frame),
                });
            }
            points
        });
        Layout {
            scale_ms,
            ticks: [0.0, 0.5, 1.0]
                .iter()
                .map(|&k| (k * scale_ms, y(k * scale_ms)))
                .collect(),
            series,
            span: [self.first, self.first + self.capacity as u64 - 1],
        }
    }
}

/// The smallest of 1, 2, 2.5 and 5 times a power of ten that is at least `ms` (1 ms for
/// nothing to show), so the axis' labels are round.
#[must_use]
pub fn round_up(ms: f64) -> f64 {
    if !ms.is_finite() || ms <= 1.0 {
        return 1.0;
    }
    let decade = 10_f64.powf(ms.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|k| k * decade)
        .find(|&v| v >= ms)
        .unwrap_or(10.0 * decade)
}

#[cfg(test)]
mod tests {
    use super::*;

    const AREA: Area = Area {
        left: 10.0,
        top: 5.0,
        width: 100.0,
        height: 50.0,
    };

    #[test]
    fn round_numbers_bound_the_times() {
        for (ms, want) in [
            (0.0, 1.0),
            (0.3, 1.0),
            (1.5, 2.0),
            (2.1, 2.5),
            (4.9, 5.0),
            (5.1, 10.0),
            (10.0, 10.0),
            (637.0, 1000.0),
            (1130.0, 2000.0),
            (f64::NAN, 1.0),
        ] {
            assert_eq!(round_up(ms), want, "{ms}");
        }
    }

    #[test]
    fn one_point_per_frame_per_series_and_gaps_break_the_line() {
        let mut t = FrameTimes::new(8);
        for frame in 0..6 {
            t.record(frame, 0, 10.0 + frame as f64);
            // The fixed side skips frame 3 (side by side turned off there).
            if frame != 3 {
                t.record(frame, 1, 20.0);
            }
        }
        assert_eq!((t.len(), t.points(0), t.points(1)), (6, 6, 5));
        let l = t.layout(AREA);
        assert_eq!(l.series[0].len(), 6);
        assert_eq!(l.series[1].len(), 5);
        let joined: Vec<bool> = l.series[1].iter().map(|p| p.joined).collect();
        assert_eq!(joined, [false, true, true, false, true]);
        // The axis spans the capacity, not only the frames held so far.
        assert_eq!(l.span, [0, 7]);
        // Frame k at left + k * width / (capacity - 1).
        for p in &l.series[0] {
            assert!((p.x - (10.0 + p.frame as f64 * 100.0 / 7.0)).abs() < 1e-9);
        }
    }

    #[test]
    fn the_scale_leaves_out_frame_zero_and_clips_it() {
        let mut t = FrameTimes::new(4);
        t.record(0, 0, 900.0);
        for frame in 1..4 {
            t.record(frame, 0, 40.0);
        }
        let l = t.layout(AREA);
        assert_eq!(l.scale_ms, 50.0);
        let p = &l.series[0];
        assert!(p[0].clipped && p[0].y == AREA.top, "{:?}", p[0]);
        // 40 of 50 ms: four fifths of the way up.
        assert!(
            p[1..]
                .iter()
                .all(|q| !q.clipped && (q.y - 15.0).abs() < 1e-9)
        );
        assert_eq!(l.ticks, vec![(0.0, 55.0), (25.0, 30.0), (50.0, 5.0)]);
        // Frame 0 alone sets the scale.
        let mut alone = FrameTimes::new(4);
        alone.record(0, 1, 900.0);
        assert_eq!(alone.layout(AREA).scale_ms, 1000.0);
    }

    #[test]
    fn the_window_rolls_and_refuses_what_it_cannot_place() {
        let mut t = FrameTimes::new(3);
        for frame in 0..5 {
            t.record(frame, 0, 1.0);
        }
        assert_eq!(t.len(), 3);
        let frames: Vec<u64> = t.layout(AREA).series[0].iter().map(|p| p.frame).collect();
        assert_eq!(frames, [2, 3, 4]);
        assert_eq!(t.layout(AREA).span, [2, 4]);
        t.record(1, 0, 5.0);
        t.record(4, 2, 5.0);
        t.record(4, 1, f64::NAN);
        t.record(4, 1, -1.0);
        assert_eq!((t.len(), t.points(0), t.points(1)), (3, 3, 0));
        assert!(FrameTimes::new(3).is_empty());
        // A frame far ahead starts the window afresh, the frames between without points.
        t.record(1_000_000, 0, 2.0);
        assert_eq!((t.len(), t.points(0)), (3, 1));
        assert_eq!(t.layout(AREA).series[0][0].frame, 1_000_000);
    }
}
