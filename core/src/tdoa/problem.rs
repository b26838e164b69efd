//! The typed, validated TDOA problem (`nvector-tdoa/1`): what
//! [`crate::format::tdoa::TdoaDoc`] reads, checked (dimensions, ids, counts,
//! a positive propagation speed) with the JSON path of every error.

use crate::error::InputError;
use crate::format::leaf::{BoxIn, Integer, List};
use crate::format::tdoa::{PulseDoc, ReceiverDoc, TdoaDoc, TdoaTruthDoc};
use crate::format::{from_str, from_value};
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use serde_json::Value;

/// The format name of the input.
pub const FORMAT: &str = "nvector-tdoa/1";
/// Most emitters, and the largest emitter id plus one.
pub const MAX_EMITTERS: u64 = 1 << 20;

/// A receiver: its surveyed position (a 3-D box) and clock bias.
#[derive(Debug, Clone, PartialEq)]
pub struct Receiver {
    /// Where it is (x east, y north, z up, metres).
    pub position: IntervalBox,
    /// Its clock's bias (s): a time stamp is the true arrival plus it.
    pub clock_bias: Interval,
}

/// One time stamp of a pulse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arrival {
    /// Index into [`TdoaProblem::receivers`].
    pub receiver: usize,
    /// The time stamp's interval (s).
    pub time: Interval,
}

/// One pulse: its arrivals and what is known of its emitter.
#[derive(Debug, Clone, PartialEq)]
pub struct Pulse {
    /// Its time stamps.
    pub arrivals: Vec<Arrival>,
    /// An interval of the emitter's z.
    pub altitude: Option<Interval>,
    /// A box of the emitter.
    pub region: Option<IntervalBox>,
    /// The operator's emitter id.
    pub emitter: Option<usize>,
    /// A distance cut: (point box, distance interval).
    pub distance_from: Option<(IntervalBox, Interval)>,
}

/// The truth of a simulated or surveyed problem.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TdoaTruth {
    /// Per pulse, its emitter's position (None: unknown).
    pub positions: Vec<Option<[f64; 3]>>,
    /// The emitters' positions.
    pub emitters: Vec<[f64; 3]>,
    /// Per pulse, its emitter id (None: unknown or a false pulse).
    pub matching: Vec<Option<usize>>,
}

/// A validated `nvector-tdoa/1` problem.
#[derive(Debug, Clone, PartialEq)]
pub struct TdoaProblem {
    /// Its name.
    pub name: String,
    /// The propagation speed c (m/s), positive.
    pub speed: Interval,
    /// The receivers.
    pub receivers: Vec<Receiver>,
    /// The pulses.
    pub pulses: Vec<Pulse>,
    /// n: at most n emitters (atmost_nvector over the pulses' positions).
    pub emitter_count: Option<usize>,
    /// Box of every emitter.
    pub emitter_region: Option<IntervalBox>,
    /// q, counted in arrivals.
    pub max_outliers: usize,
    /// The `meta` object (null when absent).
    pub meta: Value,
    /// The truth, when given.
    pub truth: Option<TdoaTruth>,
}

fn missing(path: &str) -> InputError {
    InputError::new(path, "missing required field")
}

fn box3(b: &BoxIn, path: &str) -> Result<IntervalBox, InputError> {
    b.dim(path, Some(3))
}

fn int(x: Integer, max: u64, path: &str) -> Result<usize, InputError> {
    x.at_most(max, path).map(|v| v as usize)
}

impl TdoaProblem {
    /// Parses and validates JSON text.
    pub fn from_json_str(text: &str) -> Result<TdoaProblem, InputError> {
        TdoaProblem::from_doc(from_str::<TdoaDoc>(text)?)
    }

    /// Validates a parsed JSON value.
    pub fn from_value(v: &Value) -> Result<TdoaProblem, InputError> {
        TdoaProblem::from_doc(from_value::<TdoaDoc>(v)?)
    }

    /// Validates the serde document.
    pub fn from_doc(doc: TdoaDoc) -> Result<TdoaProblem, InputError> {
        match doc.format.as_ref() {
            None => return Err(missing("format")),
            Some(Value::String(s)) if s == FORMAT => {}
            Some(_) => return Err(InputError::new("format", format!("expected \"{FORMAT}\""))),
        }
        let speed = doc
            .propagation_speed
            .ok_or_else(|| missing("propagation_speed"))?
            .0;
        if speed.lo().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(InputError::new(
                "propagation_speed",
                "the propagation speed must be positive (lower bound > 0)",
            ));
        }
        let receivers = receivers(doc.receivers.ok_or_else(|| missing("receivers"))?)?;
        let emitter_count = doc
            .emitter_count
            .map(|n| n.in_range(1, MAX_EMITTERS, "emitter_count"))
            .transpose()?
            .map(|n| n as usize);
        let pulse_docs = doc.pulses.ok_or_else(|| missing("pulses"))?;
        let pulses = pulses(pulse_docs, receivers.len(), emitter_count)?;
        let arrivals: usize = pulses.iter().map(|p| p.arrivals.len()).sum();
        // As for missions (docs/formats.md): any q up to u32::MAX, and a q
        // above the arrival count reads as that count (every arrival
        // dropped at most); nothing is sized by q beyond it.
        let max_outliers = match doc.max_outliers {
            None => 0,
            Some(q) => int(q, u64::from(u32::MAX), "max_outliers")?.min(arrivals),
        };
        let emitter_region = doc
            .emitter_region
            .map(|b| box3(&b, "emitter_region"))
            .transpose()?;
        let meta = match doc.meta {
            None => Value::Null,
            Some(m @ Value::Object(_)) => m,
            Some(_) => return Err(InputError::new("meta", "expected an object")),
        };
        let truth = doc.truth.map(|t| truth(t, pulses.len())).transpose()?;
        Ok(TdoaProblem {
            name: doc.name.unwrap_or_else(|| "tdoa".into()),
            speed,
            receivers,
            pulses,
            emitter_count,
            emitter_region,
            max_outliers,
            meta,
            truth,
        })
    }
}

fn receivers(docs: List<ReceiverDoc>) -> Result<Vec<Receiver>, InputError> {
    let mut out = Vec::with_capacity(docs.0.len());
    for (i, r) in docs.0.into_iter().enumerate() {
        let path = format!("receivers[{i}]");
        let position = r
            .position
            .ok_or_else(|| missing(&format!("{path}.position")))?;
        out.push(Receiver {
            position: box3(&position, &format!("{path}.position"))?,
            clock_bias: r.clock_bias.map_or(Interval::ZERO, |b| b.0),
        });
    }
    Ok(out)
}

fn pulses(
    docs: List<PulseDoc>,
    receivers: usize,
    emitter_count: Option<usize>,
) -> Result<Vec<Pulse>, InputError> {
    let ids = emitter_count.unwrap_or(docs.0.len().max(1));
    let mut out = Vec::with_capacity(docs.0.len());
    for (k, p) in docs.0.into_iter().enumerate() {
        let path = format!("pulses[{k}]");
        let list = p
            .arrivals
            .ok_or_else(|| missing(&format!("{path}.arrivals")))?;
        let mut arrivals = Vec::with_capacity(list.0.len());
        for (a, doc) in list.0.into_iter().enumerate() {
            let at = format!("{path}.arrivals[{a}]");
            let r = doc
                .receiver
                .ok_or_else(|| missing(&format!("{at}.receiver")))?;
            let receiver = match r {
                Integer::Value(x) if (x as usize) < receivers && x < u64::MAX => x as usize,
                _ => {
                    return Err(InputError::new(
                        format!("{at}.receiver"),
                        format!("no such receiver (there are {receivers})"),
                    ))
                }
            };
            let time = doc.time.ok_or_else(|| missing(&format!("{at}.time")))?.0;
            arrivals.push(Arrival { receiver, time });
        }
        let emitter = match p.emitter {
            None => None,
            Some(Integer::Value(x)) if x < ids as u64 => Some(x as usize),
            Some(_) => {
                return Err(InputError::new(
                    format!("{path}.emitter"),
                    format!("an emitter id is below emitter_count ({ids})"),
                ))
            }
        };
        let distance_from = match p.distance_from {
            None => None,
            Some(d) => {
                let at = format!("{path}.distance_from");
                let point = d.point.ok_or_else(|| missing(&format!("{at}.point")))?;
                let range = d.range.ok_or_else(|| missing(&format!("{at}.range")))?.0;
                Some((box3(&point, &format!("{at}.point"))?, range))
            }
        };
        out.push(Pulse {
            distance_from,
            arrivals,
            altitude: p.altitude.map(|a| a.0),
            region: p
                .region
                .map(|b| box3(&b, &format!("{path}.region")))
                .transpose()?,
            emitter,
        });
    }
    Ok(out)
}

fn point3(p: &List<crate::format::leaf::Finite>, path: &str) -> Result<[f64; 3], InputError> {
    match p.0.as_slice() {
        [x, y, z] => Ok([x.0, y.0, z.0]),
        _ => Err(InputError::new(
            path,
            format!("expected a point of 3 coordinates, found {}", p.0.len()),
        )),
    }
}

fn truth(t: TdoaTruthDoc, pulses: usize) -> Result<TdoaTruth, InputError> {
    let mut out = TdoaTruth::default();
    if let Some(ps) = t.positions {
        if ps.0.len() != pulses {
            return Err(InputError::new(
                "truth.positions",
                format!(
                    "expected {pulses} entries (one per pulse), found {}",
                    ps.0.len()
                ),
            ));
        }
        for (k, p) in ps.0.iter().enumerate() {
            let path = format!("truth.positions[{k}]");
            out.positions
                .push(p.as_ref().map(|p| point3(p, &path)).transpose()?);
        }
    } else {
        out.positions = vec![None; pulses];
    }
    for (j, e) in t
        .emitters
        .map(|l| l.0)
        .unwrap_or_default()
        .iter()
        .enumerate()
    {
        out.emitters
            .push(point3(e, &format!("truth.emitters[{j}]"))?);
    }
    if let Some(m) = t.matching {
        if m.0.len() != pulses {
            return Err(InputError::new(
                "truth.matching",
                format!(
                    "expected {pulses} entries (one per pulse), found {}",
                    m.0.len()
                ),
            ));
        }
        for (k, e) in m.0.iter().enumerate() {
            out.matching.push(match e {
                None => None,
                Some(Integer::Value(x)) if (*x as usize) < out.emitters.len().max(pulses) => {
                    Some(*x as usize)
                }
                Some(_) => {
                    return Err(InputError::new(
                        format!("truth.matching[{k}]"),
                        "no such emitter in truth.emitters",
                    ))
                }
            });
        }
    } else {
        out.matching = vec![None; pulses];
    }
    Ok(out)
}
