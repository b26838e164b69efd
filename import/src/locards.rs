//! LocaRDS multilateration messages (`data/locards-mlat`, README there;
//! `nvector import --locards-mlat DIR [--set N]`) as an `nvector-tdoa/1`
//! problem, one pulse per message (docs/tdoa.md).
//!
//! - Frame: WGS84 geodetic to ECEF (closed form), then to a local ENU
//!   frame at the sensor nearest the sensors' mean (nalgebra for the rotation). The
//!   f64 rounding of the conversion (a few dozen operations on values below
//!   7e6 m: below 1e-6 m) is covered by widening every receiver box by
//!   [`ROUNDING_M`].
//! - Times: per message, nanoseconds minus the message's earliest (exact
//!   integer arithmetic), then seconds (relative rounding 1e-16, covered by
//!   [`ROUNDING_S`]); clock biases 0 (GPS-timed receivers).
//! - Bounds from the data against the truth (the aircraft's reported
//!   position and geometric altitude): the residual of each arrival,
//!   `time - |truth - receiver| / c0`, minus the message's midrange offset;
//!   every time stamp gets `± (MARGIN · max |residual| + SLACK_S)` over the
//!   set (the tail handled by wider bounds: docs/tdoa.md argues why), all
//!   figures in `meta`.

use crate::ImportError;
use nalgebra::{Matrix3, Vector3};
use nvector_core::format::leaf::{BoxIn, Finite, Integer, IntervalIn, List};
use nvector_core::format::tdoa::TdoaTruthDoc;
use nvector_core::format::tdoa::{ArrivalDoc, DistanceFromDoc, PulseDoc, ReceiverDoc, TdoaDoc};
use nvector_core::Interval;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::path::Path;

/// Widening of every receiver coordinate for the conversion's rounding (m).
pub const ROUNDING_M: f64 = 1e-3;
/// Widening of every time stamp for the ns-to-s rounding (s).
pub const ROUNDING_S: f64 = 1e-12;
/// The stated margin: the bound is this times the largest residual, plus
/// [`SLACK_S`].
pub const MARGIN: f64 = 1.1;
/// Added to every time bound (s).
pub const SLACK_S: f64 = 20e-9;
/// Propagation speed bounds (air, refractive index 1 to 1.0003) and the
/// nominal c0 the residuals use (index 1.00015).
pub const SPEED: [f64; 2] = [299_702_547.0, 299_792_458.0];
const C0: f64 = 299_792_458.0 / 1.00015;

/// One message: the truth and the arrivals (sensor serial, ns).
struct Message {
    id: u64,
    lat: f64,
    lon: f64,
    geo_alt: f64,
    baro_alt: f64,
    arrivals: Vec<(u64, i64)>,
}

/// WGS84 geodetic (degrees, metres) to ECEF (metres).
pub fn ecef(lat: f64, lon: f64, h: f64) -> Vector3<f64> {
    let (a, f) = (6_378_137.0, 1.0 / 298.257_223_563);
    let e2 = f * (2.0 - f);
    let (la, lo) = (lat.to_radians(), lon.to_radians());
    let n = a / (1.0 - e2 * la.sin() * la.sin()).sqrt();
    Vector3::new(
        (n + h) * la.cos() * lo.cos(),
        (n + h) * la.cos() * lo.sin(),
        (n * (1.0 - e2) + h) * la.sin(),
    )
}

/// The local east-north-up frame at a geodetic point.
pub struct Frame {
    origin: Vector3<f64>,
    rot: Matrix3<f64>,
}

impl Frame {
    /// The frame at (lat, lon, h).
    pub fn new(lat: f64, lon: f64, h: f64) -> Frame {
        let (la, lo) = (lat.to_radians(), lon.to_radians());
        let rot = Matrix3::new(
            -lo.sin(),
            lo.cos(),
            0.0,
            -la.sin() * lo.cos(),
            -la.sin() * lo.sin(),
            la.cos(),
            la.cos() * lo.cos(),
            la.cos() * lo.sin(),
            la.sin(),
        );
        Frame {
            origin: ecef(lat, lon, h),
            rot,
        }
    }

    /// ENU coordinates of the Earth's centre.
    pub fn centre(&self) -> [f64; 3] {
        let v = self.rot * -self.origin;
        [v.x, v.y, v.z]
    }

    /// ENU coordinates of a geodetic point.
    pub fn enu(&self, lat: f64, lon: f64, h: f64) -> [f64; 3] {
        let v = self.rot * (ecef(lat, lon, h) - self.origin);
        [v.x, v.y, v.z]
    }
}

fn field(cols: &[&str], i: usize, file: &Path, line: usize) -> Result<f64, ImportError> {
    cols.get(i)
        .and_then(|s| s.trim().parse::<f64>().ok())
        .filter(|x| x.is_finite())
        .ok_or_else(|| ImportError::line(file, line, format!("column {} is not a number", i + 1)))
}

fn read_sensors(dir: &Path) -> Result<HashMap<u64, [f64; 3]>, ImportError> {
    let file = dir.join("sensors.csv");
    let text = std::fs::read_to_string(&file).map_err(|e| ImportError::read(&file, e))?;
    let mut out = HashMap::new();
    for (i, l) in text
        .lines()
        .enumerate()
        .skip(1)
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let c: Vec<&str> = l.split(',').collect();
        let serial = field(&c, 0, &file, i + 1)? as u64;
        out.insert(
            serial,
            [
                field(&c, 1, &file, i + 1)?,
                field(&c, 2, &file, i + 1)?,
                field(&c, 3, &file, i + 1)?,
            ],
        );
    }
    Ok(out)
}

fn read_set(dir: &Path, set: u32) -> Result<Vec<Message>, ImportError> {
    let file = dir.join(format!("set_{set}.csv"));
    let text = std::fs::read_to_string(&file).map_err(|e| ImportError::read(&file, e))?;
    let mut out = Vec::new();
    for (i, l) in text
        .lines()
        .enumerate()
        .skip(1)
        .filter(|(_, l)| !l.trim().is_empty())
    {
        let line = i + 1;
        let (head, quoted) = l
            .split_once('"')
            .ok_or_else(|| ImportError::line(&file, line, "no quoted measurements column"))?;
        let c: Vec<&str> = head.split(',').collect();
        let list: Vec<Vec<f64>> = serde_json::from_str(quoted.trim_end().trim_end_matches('"'))
            .map_err(|e| ImportError::line(&file, line, format!("measurements: {e}")))?;
        let arrivals = list
            .iter()
            .map(|m| match m.as_slice() {
                [s, t, _] if s.fract() == 0.0 && t.fract() == 0.0 && t.abs() < 9e15 => {
                    Ok((*s as u64, *t as i64))
                }
                _ => Err(ImportError::line(
                    &file,
                    line,
                    "a measurement is [serial, ns, strength]",
                )),
            })
            .collect::<Result<Vec<_>, _>>()?;
        out.push(Message {
            id: field(&c, 0, &file, line)? as u64,
            lat: field(&c, 3, &file, line)?,
            lon: field(&c, 4, &file, line)?,
            geo_alt: field(&c, 6, &file, line)?,
            baro_alt: field(&c, 5, &file, line)?,
            arrivals,
        });
    }
    Ok(out)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Per message: (seconds since its first arrival, per arrival) and the
/// half-range of its residuals against the truth.
fn residual_half_range(m: &Message, truth: [f64; 3], rx: &[[f64; 3]]) -> f64 {
    let t0 = m.arrivals.iter().map(|a| a.1).min().unwrap_or(0);
    let r: Vec<f64> = m
        .arrivals
        .iter()
        .zip(rx)
        .map(|(a, p)| (a.1 - t0) as f64 * 1e-9 - dist(truth, *p) / C0)
        .collect();
    let lo = r.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = r.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (hi - lo) / 2.0
}

/// The problem of set `set` of the LocaRDS directory `dir` (the file
/// `set_{set}.csv` and `sensors.csv`), validated as core reads it.
pub fn locards(dir: &Path, set: u32) -> Result<Value, ImportError> {
    let sensors = read_sensors(dir)?;
    let messages = read_set(dir, set)?;
    let mut serials: Vec<u64> = messages
        .iter()
        .flat_map(|m| m.arrivals.iter().map(|a| a.0))
        .collect();
    serials.sort_unstable();
    serials.dedup();
    let geo = |s: u64| {
        sensors.get(&s).copied().ok_or_else(|| {
            ImportError::file(
                format!("set_{set}.csv"),
                format!("sensor {s} is not in sensors.csv"),
            )
        })
    };
    if serials.is_empty() {
        return Err(ImportError::file(format!("set_{set}.csv"), "no message"));
    }
    // The frame at the sensor nearest the sensors' mean (ECEF).
    let pts = serials
        .iter()
        .map(|&s| geo(s).map(|g| ecef(g[0], g[1], g[2])))
        .collect::<Result<Vec<_>, _>>()?;
    let mean = pts.iter().fold(Vector3::zeros(), |a, p| a + p) / pts.len() as f64;
    let near = (0..pts.len())
        .min_by(|&a, &b| (pts[a] - mean).norm().total_cmp(&(pts[b] - mean).norm()))
        .unwrap_or(0);
    let o = geo(serials[near])?;
    let frame = Frame::new(o[0], o[1], o[2]);
    let mut index = HashMap::new();
    let mut rx = Vec::new();
    for &s in &serials {
        let g = geo(s)?;
        index.insert(s, rx.len());
        rx.push(frame.enu(g[0], g[1], g[2]));
    }
    let truths: Vec<[f64; 3]> = messages
        .iter()
        .map(|m| frame.enu(m.lat, m.lon, m.geo_alt))
        .collect();
    let halves: Vec<f64> = messages
        .iter()
        .zip(&truths)
        .map(|(m, t)| {
            let ps: Vec<[f64; 3]> = m.arrivals.iter().map(|a| rx[index[&a.0]]).collect();
            residual_half_range(m, *t, &ps)
        })
        .collect();
    let mut sorted = halves.clone();
    sorted.sort_by(f64::total_cmp);
    let worst = sorted.last().copied().unwrap_or(0.0);
    let w = MARGIN * worst + SLACK_S + ROUNDING_S;
    let (alt, lats) = altitude_bounds(set, &messages, &geo)?;
    let cuts = altitude_cuts(&messages, &frame, &lats, alt);
    let mut doc = problem(set, &messages, &rx, &index, &truths, w, &sorted, o);
    for (pulse, c) in doc.pulses.iter_mut().flat_map(|p| &mut p.0).zip(cuts) {
        pulse.distance_from = Some(c);
    }
    if let Some(meta) = doc.meta.as_mut() {
        meta["altitude_bound_m"] = alt.into();
        meta["altitude_rule"] = "baroAltitude +- (1.1 x the largest |baro - geo| + 10 m), as a distance from the Earth's centre over the message's sensors' latitudes +- 4 degrees".into();
    }
    let p = nvector_core::format::to_value(&doc);
    // Whatever was built must be a valid problem.
    nvector_core::tdoa::problem::TdoaProblem::from_value(&p).map_err(ImportError::InvalidTdoa)?;
    Ok(p)
}

/// The altitude bound (m) and each message's latitude span: barometric
/// against geometric altitude, the same rule as the times, 1.1 x the
/// largest difference + 10 m; latitudes: the message's sensors' +- 4
/// degrees (aircraft are within 355 km of a receiver, 3.2 degrees).
fn altitude_bounds(
    set: u32,
    messages: &[Message],
    geo: &dyn Fn(u64) -> Result<[f64; 3], ImportError>,
) -> Result<(f64, Vec<[f64; 2]>), ImportError> {
    let alt = MARGIN
        * messages
            .iter()
            .map(|m| (m.baro_alt - m.geo_alt).abs())
            .fold(0.0, f64::max)
        + 10.0;
    let mut lats = Vec::with_capacity(messages.len());
    for m in messages {
        let mut l = [90.0f64, 0.0f64];
        for a in &m.arrivals {
            let g = geo(a.0)?;
            l = [l[0].min(g[0] - 4.0), l[1].max(g[0] + 4.0)];
        }
        if !(l[0] >= 0.0 && l[1] <= 90.0) {
            return Err(ImportError::file(
                format!("set_{set}.csv"),
                format!(
                    "message {}: the altitude cut assumes latitudes 4 to 86 degrees north",
                    m.id
                ),
            ));
        }
        lats.push(l);
    }
    Ok((alt, lats))
}

/// A point as a box widened by the rounding of its coordinates.
fn widened(p: [f64; 3]) -> BoxIn {
    BoxIn(
        p.iter()
            .map(|&c| Interval::new(c - ROUNDING_M, c + ROUNDING_M))
            .collect(),
    )
}

/// Distance from the Earth's centre of a point at geodetic latitude
/// `lat` (degrees) and height `h`.
fn geocentric(lat: f64, h: f64) -> f64 {
    let v = ecef(lat, 0.0, h);
    v.norm()
}

/// The altitude cut of each message: its barometric altitude +- `m`, as a
/// distance from the Earth's centre over the latitudes `lats` (the radius
/// decreases with |latitude| in [0, 90]), widened by 1 m for rounding.
fn altitude_cuts(
    messages: &[Message],
    frame: &Frame,
    lats: &[[f64; 2]],
    m: f64,
) -> Vec<DistanceFromDoc> {
    let c = frame.centre();
    messages
        .iter()
        .zip(lats)
        .map(|(msg, lats)| {
            let lo = geocentric(lats[1], msg.baro_alt - m) - 1.0;
            let hi = geocentric(lats[0], msg.baro_alt + m) + 1.0;
            DistanceFromDoc {
                point: Some(widened(c)),
                range: Some(IntervalIn(Interval::new(lo, hi))),
            }
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn problem(
    set: u32,
    messages: &[Message],
    rx: &[[f64; 3]],
    index: &HashMap<u64, usize>,
    truths: &[[f64; 3]],
    w: f64,
    sorted: &[f64],
    origin: [f64; 3],
) -> TdoaDoc {
    let receivers = rx
        .iter()
        .map(|&p| ReceiverDoc {
            position: Some(widened(p)),
            clock_bias: Some(IntervalIn(Interval::new(0.0, 0.0))),
        })
        .collect();
    let pulses = messages
        .iter()
        .map(|m| {
            let t0 = m.arrivals.iter().map(|a| a.1).min().unwrap_or(0);
            let arrivals = m
                .arrivals
                .iter()
                .map(|a| {
                    let t = (a.1 - t0) as f64 * 1e-9;
                    ArrivalDoc {
                        receiver: Some(Integer::Value(index[&a.0] as u64)),
                        time: Some(IntervalIn(Interval::new(t - w, t + w))),
                    }
                })
                .collect();
            PulseDoc {
                arrivals: Some(List(arrivals)),
                ..PulseDoc::default()
            }
        })
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in rx {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Horizontal reach of the region, and how far the ellipsoid (and an
    // aircraft below 20 km) drops below the tangent plane there: d^2 / 2R
    // with R = 6.3e6 m (below every radius of curvature of WGS84), x 1.2
    // for the higher-order terms, and 50 km more.
    let reach = (0..2)
        .map(|k| (lo[k] - 6e5).abs().max((hi[k] + 6e5).abs()))
        .fold(0.0f64, |a, x| a.hypot(x));
    let z_lo = -1.2 * reach * reach / (2.0 * 6.3e6) - 5e4;
    let q = |f: f64| {
        sorted
            .get(((sorted.len() as f64 - 1.0) * f) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    let point = |p: &[f64; 3]| Some(List(p.map(Finite).to_vec()));
    let region = [
        [lo[0] - 6e5, hi[0] + 6e5],
        [lo[1] - 6e5, hi[1] + 6e5],
        [z_lo, 2e4],
    ];
    TdoaDoc {
        format: Some(nvector_core::tdoa::problem::FORMAT.into()),
        name: Some(format!("locards-set-{set}")),
        propagation_speed: Some(IntervalIn(Interval::new(SPEED[0], SPEED[1]))),
        receivers: Some(List(receivers)),
        pulses: Some(List(pulses)),
        emitter_region: Some(BoxIn(
            region.iter().map(|&[a, b]| Interval::new(a, b)).collect(),
        )),
        meta: Some(json!({
            "source": format!("LocaRDS set_{set}.csv (data/locards-mlat of the nvector repository)"),
            "message_ids": messages.iter().map(|m| m.id).collect::<Vec<_>>(),
            "frame": {"origin_lat_lon_h": origin, "axes": "ENU (x east, y north, z up) at the sensor nearest the sensors' mean"},
            "time_bound_s": w,
            "time_bound_rule": format!("{MARGIN} x the largest residual half-range over the set + {SLACK_S} s + {ROUNDING_S} s rounding"),
            "residual_half_range_s": {"median": q(0.5), "p90": q(0.9), "p99": q(0.99), "max": q(1.0)},
            "nominal_speed": C0,
            "receiver_widening_m": ROUNDING_M,
        })),
        truth: Some(TdoaTruthDoc {
            positions: Some(List(truths.iter().map(point).collect())),
            ..TdoaTruthDoc::default()
        }),
        ..TdoaDoc::default()
    }
}
