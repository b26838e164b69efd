//! The CLI's figures as a person sees them: CMU Plaza 1 with the
//! beacon ids hidden, `best`, drawn by `nvector run --plot` (SVG) and
//! `nvector plot` (PNG). The PNG's pixels along the true path have the
//! truth's colour (nothing drawn over it), most of the plotting area is not
//! one solid block, and the SVG holds the title in metres, the axis labels
//! and the legend.

use nvector_tests::{run, succeeded, temp_file};
use std::path::{Path, PathBuf};

fn cmu_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    assert!(
        dir.join("Plaza1_DR.txt").exists(),
        "the CMU Plaza 1 data must be at {} (data/ of the repository)",
        dir.display()
    );
    dir
}

/// A decoded RGB PNG and its `nvector-plot-area` chunk.
struct Image {
    width: usize,
    height: usize,
    px: Vec<u8>,
    /// Plotting area in pixels: left, top, right, bottom.
    area: [f64; 4],
    /// The metres it shows: x0, x1, y0, y1.
    view: [f64; 4],
}

impl Image {
    fn read(path: &Path) -> Image {
        let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let mut px = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut px).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let chunk = reader
            .info()
            .uncompressed_latin1_text
            .iter()
            .find(|c| c.keyword == "nvector-plot-area")
            .expect("the PNG names its plotting area")
            .text
            .clone();
        let n: Vec<f64> = chunk.split(' ').map(|s| s.parse().unwrap()).collect();
        assert_eq!(n.len(), 8, "{chunk}");
        Image {
            width: info.width as usize,
            height: info.height as usize,
            px,
            area: [n[0], n[1], n[2], n[3]],
            view: [n[4], n[5], n[6], n[7]],
        }
    }

    fn at(&self, i: i64, j: i64) -> Option<[u8; 3]> {
        if i < 0 || j < 0 || i as usize >= self.width || j as usize >= self.height {
            return None;
        }
        let k = (j as usize * self.width + i as usize) * 3;
        Some([self.px[k], self.px[k + 1], self.px[k + 2]])
    }

    /// The pixel of a point in metres.
    fn pixel(&self, x: f64, y: f64) -> (i64, i64) {
        let [l, t, r, b] = self.area;
        let [x0, x1, y0, y1] = self.view;
        let i = l + (x - x0) / (x1 - x0) * (r - l);
        let j = t + (y1 - y) / (y1 - y0) * (b - t);
        (i.round() as i64, j.round() as i64)
    }
}

/// The words of an SVG as a person reads them: the text of every `<text>`
/// element, joined by spaces (a legend label wrapped on two lines reads
/// as one).
fn svg_words(svg: &str) -> String {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..];
            Some(body[..body.find("</text>")?].trim().to_string())
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The truth's colour: black (core::figure::TRUTH).
fn is_truth(c: [u8; 3]) -> bool {
    c.iter().all(|&v| v < 40)
}

#[test]
fn plaza_ids_hidden_shows_the_truth_path_with_axes_and_legend() {
    let m = temp_file("plaza.json");
    succeeded(&run(&[
        "import",
        "--cmu-plaza",
        cmu_dir().to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]));
    let r = temp_file("plaza-result.json");
    let svg = temp_file("plaza.svg");
    succeeded(&run(&[
        "run",
        m.to_str().unwrap(),
        "--contractor",
        "best",
        "--out",
        r.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]));
    let png = temp_file("plaza.png");
    let err = succeeded(&run(&[
        "plot",
        r.to_str().unwrap(),
        "--mission",
        m.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
    ]));
    assert!(!err.contains("warning"), "{err}");

    let mission: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&m).unwrap()).unwrap();
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&r).unwrap()).unwrap();
    let truth: Vec<(f64, f64)> = mission["truth"]["positions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    assert!(truth.len() > 9000);

    // The PNG: along the true path, the truth's colour within a pixel.
    let img = Image::read(&png);
    let mut hidden = Vec::new();
    for &(x, y) in truth.iter().step_by(7) {
        let (i, j) = img.pixel(x, y);
        let seen = (-1..=1)
            .flat_map(|di| (-1..=1).map(move |dj| (di, dj)))
            .any(|(di, dj)| img.at(i + di, j + dj).is_some_and(is_truth));
        if !seen {
            hidden.push((x, y, i, j, img.at(i, j)));
        }
    }
    assert!(
        hidden.is_empty(),
        "{} of {} points of the true path not drawn in black, e.g. {:?}",
        hidden.len(),
        truth.len().div_ceil(7),
        &hidden[..hidden.len().min(5)]
    );
    // The plotting area is not one solid block: white background or light
    // translucent layers on most of it (the issue's "solid red rectangle
    // hiding the trajectory" fails this).
    let [l, t, rgt, b] = img.area.map(|v| v as i64);
    let (mut light, mut all) = (0usize, 0usize);
    for j in (t..b).step_by(3) {
        for i in (l..rgt).step_by(3) {
            let c = img.at(i, j).unwrap();
            all += 1;
            if c.iter().map(|&v| u32::from(v)).sum::<u32>() > 3 * 160 {
                light += 1;
            }
        }
    }
    assert!(
        light * 10 >= all * 7,
        "only {light} of {all} pixels of the plotting area are light"
    );
    // The envelope is drawn: a point of the true path far from others is
    // over the trajectory's colour nearby (not white).
    let (x, y) = truth[truth.len() / 2];
    let (i, j) = img.pixel(x, y);
    let around: Vec<[u8; 3]> = (-6..=6)
        .filter_map(|d| img.at(i + d, j - 6))
        .chain((-6..=6).filter_map(|d| img.at(i + 6, j + d)))
        .collect();
    assert!(
        around
            .iter()
            .any(|c| *c != [255, 255, 255] && !is_truth(*c)),
        "no trajectory colour around the path at ({x}, {y})"
    );

    // The SVG: title in metres, axes, legend.
    let svg_text = std::fs::read_to_string(&svg).unwrap();
    assert!(svg_text.starts_with("<svg"));
    let text = svg_words(&svg_text);
    let max = result["metrics"]["max_trajectory_diameter"]
        .as_f64()
        .unwrap();
    for wanted in [
        format!("max trajectory diameter {max:.1} m"),
        "x (m)".to_string(),
        "y (m)".to_string(),
        "Legend".to_string(),
        "true path".to_string(),
        "true landmarks".to_string(),
        format!(
            "trajectory: envelope of the {}",
            result["trajectory"].as_array().unwrap().len()
        ),
        format!(
            "{} proved groups of at most 4 landmarks",
            result["matching"].as_array().unwrap().len()
        ),
    ] {
        assert!(text.contains(&wanted), "the SVG lacks '{wanted}'");
    }
    // A handful of group outlines, not one per group.
    assert!(text.contains("tightest outlined"), "outlines not thinned");
}

/// Unbounded, overflowing and empty values, and a result with nothing to
/// draw: a figure all the same (never a panic), the undrawn boxes counted.
#[test]
fn huge_unbounded_and_empty_results_are_drawn_without_failing() {
    // Every field a result must have (plot reads it through core's types).
    let options = serde_json::json!({"contractor": "best", "max_rounds": 10, "tolerance": 0});
    let metrics = |diameter: serde_json::Value| {
        serde_json::json!({"contractions": 0, "elapsed_ms": 0, "matched_detections": 0,
            "max_detection_diameter": 0, "max_trajectory_diameter": diameter,
            "mean_trajectory_diameter": diameter, "rounds": 0})
    };
    let result = serde_json::json!({
        "format": "nvector-result/1", "mission": "u", "status": "consistent",
        "options": options,
        "trajectory": [[["-inf", "inf"], ["-inf", "inf"]], [[-1e308, 1e308], [0, 1]],
                       [[1e300, 1.7e308], [-1.7e308, -1e300]], "empty"],
        "detections": [[[-1e308, 1e308], [5, 6]]],
        "landmarks": [[[0, 0], [0, 0]]],
        "matching": [[0]],
        "metrics": metrics("inf".into())
    });
    // A valid mission of 3 steps (plot reads its mission as `run` does),
    // its truth moved to the extremes.
    let sim = temp_file("huge-sim.json");
    succeeded(&run(&[
        "simulate",
        "--scenario",
        "paper",
        "--steps",
        "3",
        "--seed",
        "1",
        "--out",
        sim.to_str().unwrap(),
    ]));
    let mut mission: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&sim).unwrap()).unwrap();
    mission["name"] = serde_json::json!("u");
    mission["truth"]["positions"] =
        serde_json::json!([[0, 0], [1e308, -1e308], [5, 5], [-1.7e308, 1.7e308]]);
    // The least result: one empty box, nothing matched.
    let empty = serde_json::json!({
        "format": "nvector-result/1", "mission": "u", "status": "infeasible",
        "reason": "step 0: empty", "options": options,
        "trajectory": ["empty"], "detections": [], "landmarks": [], "matching": [],
        "metrics": metrics(0.into())
    });
    let mut huge_svg = None;
    for (name, r, m) in [("huge", &result, &mission), ("empty", &empty, &mission)] {
        let rp = temp_file(&format!("{name}-r.json"));
        let mp = temp_file(&format!("{name}-m.json"));
        std::fs::write(&rp, r.to_string()).unwrap();
        std::fs::write(&mp, m.to_string()).unwrap();
        for ext in ["svg", "png"] {
            let out = temp_file(&format!("{name}.{ext}"));
            succeeded(&run(&[
                "plot",
                rp.to_str().unwrap(),
                "--mission",
                mp.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ]));
            assert!(std::fs::metadata(&out).unwrap().len() > 1000);
            if (name, ext) == ("huge", "svg") {
                huge_svg = Some(out);
            }
        }
    }
    let svg = svg_words(&std::fs::read_to_string(huge_svg.unwrap()).unwrap());
    assert!(svg.contains("max trajectory diameter unbounded"), "{svg}");
    assert!(
        svg.contains("trajectory: 2 position boxes (2 more unbounded or empty, not drawn)"),
        "{svg}"
    );
}

/// An edit of a (result, mission) pair.
type Edit = Box<dyn Fn(&mut serde_json::Value, &mut serde_json::Value)>;

/// `plot` checks what it draws from: a result or a mission with an
/// unknown field, a reversed interval, a group naming no detection, or a
/// mission file that is not a mission is refused, named, exit 1 (each was
/// drawn, or drawn without its truth, exit 0).
#[test]
fn plot_refuses_a_broken_result_or_mission_naming_the_fault() {
    let (mission, result, _, _) = drawn("paper", "40");
    let plot = |r: &serde_json::Value, m: &serde_json::Value, name: &str| {
        let rp = temp_file(&format!("refuse-{name}-r.json"));
        let mp = temp_file(&format!("refuse-{name}-m.json"));
        std::fs::write(&rp, r.to_string()).unwrap();
        std::fs::write(&mp, m.to_string()).unwrap();
        run(&[
            "plot",
            rp.to_str().unwrap(),
            "--mission",
            mp.to_str().unwrap(),
            "--out",
            temp_file(&format!("refuse-{name}.svg")).to_str().unwrap(),
        ])
    };
    succeeded(&plot(&result, &mission, "whole"));
    let edits: Vec<(&str, Edit, &str)> = vec![
        (
            "unknown",
            Box::new(|r, _| r["bogus"] = serde_json::json!(1)),
            "bogus: unknown field",
        ),
        (
            "reversed",
            Box::new(|r, _| r["trajectory"][2][0] = serde_json::json!([3, 2])),
            "trajectory[2][0]: lower bound 3",
        ),
        (
            "index",
            Box::new(|r, _| {
                r["matching"] = serde_json::json!([[0, 99999]]);
                r["landmarks"] = serde_json::json!([[[0, 1], [0, 1]]]);
            }),
            "matching[0][",
        ),
        (
            "status",
            Box::new(|r, _| r["status"] = serde_json::json!("weird")),
            "status:",
        ),
        (
            "mission",
            Box::new(|_, m| m["landmark_cuont"] = serde_json::json!(4)),
            "landmark_cuont: unknown field",
        ),
        (
            "not a mission",
            Box::new(|_, m| *m = serde_json::json!({})),
            "format",
        ),
    ];
    for (name, edit, want) in edits {
        let (mut r, mut m) = (result.clone(), mission.clone());
        edit(&mut r, &mut m);
        let out = plot(&r, &m, name);
        assert_eq!(out.status.code(), Some(1), "{name}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{name}: {err}");
    }
}

/// The heading marks' outline colour (core::figure::HEADINGS, #e67e22),
/// with some tolerance.
fn is_heading(c: [u8; 3]) -> bool {
    let [r, g, b] = c.map(i32::from);
    r >= 200 && (90..=170).contains(&g) && b <= 90 && r - g >= 60
}

/// Simulates `scenario` with `steps` steps, runs it with `none` and draws
/// it as SVG (`run --plot`) and PNG (`plot`): (mission, result, SVG's
/// words, PNG).
fn drawn(scenario: &str, steps: &str) -> (serde_json::Value, serde_json::Value, String, Image) {
    let m = temp_file(&format!("{scenario}.json"));
    succeeded(&run(&[
        "simulate",
        "--scenario",
        scenario,
        "--steps",
        steps,
        "--seed",
        "3",
        "--out",
        m.to_str().unwrap(),
    ]));
    let r = temp_file(&format!("{scenario}-result.json"));
    let svg = temp_file(&format!("{scenario}.svg"));
    succeeded(&run(&[
        "run",
        m.to_str().unwrap(),
        "--contractor",
        "none",
        "--out",
        r.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]));
    let png = temp_file(&format!("{scenario}.png"));
    succeeded(&run(&[
        "plot",
        r.to_str().unwrap(),
        "--mission",
        m.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
    ]));
    let read = |p: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    (
        read(&m),
        read(&r),
        svg_words(&std::fs::read_to_string(&svg).unwrap()),
        Image::read(&png),
    )
}

/// The pixels of the plotting area in the headings' colour.
fn heading_pixels(img: &Image) -> usize {
    let [l, t, r, b] = img.area.map(|v| v as i64);
    (t..b)
        .flat_map(|j| (l..r).map(move |i| (i, j)))
        .filter(|&(i, j)| img.at(i, j).is_some_and(is_heading))
        .count()
}

/// An odometry2d result's figure draws its headings (wedges
/// from the position boxes' centres, in the legend as "heading
/// (interval)") and the true headings; a unicycle2d figure has none.
#[test]
fn odometry2d_figures_draw_the_headings_and_unicycle2d_ones_do_not() {
    let (mission, result, words, img) = drawn("woods", "150");
    assert_eq!(result["headings"].as_array().unwrap().len(), 151);
    for wanted in ["heading (interval) at every", "true heading", "true path"] {
        assert!(words.contains(wanted), "the SVG lacks '{wanted}': {words}");
    }
    // Each wedge's arc, where core's description puts it, is drawn in the
    // headings' colour within 2 pixels; the wedge's apex is the centre of
    // that step's position box (read from the result, not the figure).
    let doc = nvector_core::format::result::read_value(&result).unwrap();
    let fig = nvector_core::figure::describe(&doc, Some(&mission));
    let wedges = fig
        .layers
        .iter()
        .filter(|l| l.name.starts_with("headings"))
        .flat_map(|l| l.polygons.iter().map(move |p| (l.name == "headings", p)))
        .collect::<Vec<_>>();
    assert!(wedges.len() >= 30, "{} heading marks", wedges.len());
    let centres: Vec<[f64; 2]> = result["trajectory"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| {
            let m = |a: &serde_json::Value| (a[0].as_f64().unwrap() + a[1].as_f64().unwrap()) / 2.0;
            [m(&b[0]), m(&b[1])]
        })
        .collect();
    let mut missing = Vec::new();
    for &(is_wedge, w) in &wedges {
        if is_wedge {
            assert!(
                centres
                    .iter()
                    .any(|c| (c[0] - w[0][0]).abs() < 1e-9 && (c[1] - w[0][1]).abs() < 1e-9),
                "a wedge's apex {:?} is no position box's centre",
                w[0]
            );
        }
        let p = w[w.len() / 2 + 1];
        let (i, j) = img.pixel(p[0], p[1]);
        let seen = (-2..=2)
            .flat_map(|di| (-2..=2).map(move |dj| (di, dj)))
            .any(|(di, dj)| img.at(i + di, j + dj).is_some_and(is_heading));
        if !seen {
            missing.push(p);
        }
    }
    // The truth's ticks and path are drawn over some of them.
    assert!(
        missing.len() * 5 <= wedges.len(),
        "{} of {} heading marks not drawn, e.g. {:?}",
        missing.len(),
        wedges.len(),
        &missing[..missing.len().min(3)]
    );
    assert!(heading_pixels(&img) > 200);

    let (_, result, words, img) = drawn("paper", "300");
    assert!(result.get("headings").is_none());
    assert!(!words.contains("heading"), "{words}");
    assert_eq!(heading_pixels(&img), 0);
}
