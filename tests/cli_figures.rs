//! The CLI's figures as a person sees them (issue 21): CMU Plaza 1 with the
//! beacon ids hidden, `best`, drawn by `nvector run --plot` (SVG) and
//! `nvector plot` (PNG). The PNG's pixels along the true path have the
//! truth's colour (nothing drawn over it), most of the plotting area is not
//! one solid block, and the SVG holds the title in metres, the axis labels
//! and the legend.

use nvector_tests::{run, succeeded, temp_file};
use std::path::{Path, PathBuf};

fn cmu_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/cmu-plaza1");
    assert!(
        dir.join("Plaza1_DR.txt").exists(),
        "the CMU Plaza 1 data must be at {} (../shared beside the repository)",
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
    let result = serde_json::json!({
        "format": "nvector-result/1", "mission": "u", "status": "consistent",
        "options": {"contractor": "best"},
        "trajectory": [[["-inf", "inf"], ["-inf", "inf"]], [[-1e308, 1e308], [0, 1]],
                       [[1e300, 1.7e308], [-1.7e308, -1e300]], "empty"],
        "detections": [[[-1e308, 1e308], [5, 6]]],
        "landmarks": [[[0, 0], [0, 0]]],
        "matching": [[0]],
        "metrics": {"max_trajectory_diameter": "inf", "mean_trajectory_diameter": "inf"}
    });
    let mission = serde_json::json!({
        "name": "u", "steps": 3,
        "truth": {"positions": [[0, 0], [1e308, -1e308], [5, 5], [-1.7e308, 1.7e308]],
                  "landmarks": [[0, 0]]}
    });
    let empty = serde_json::json!({
        "format": "nvector-result/1", "trajectory": [], "detections": [],
        "landmarks": [], "matching": []
    });
    let mut huge_svg = None;
    for (name, r, m) in [
        ("huge", &result, &mission),
        ("empty", &empty, &serde_json::json!({})),
    ] {
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
