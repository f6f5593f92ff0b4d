//! The render report (issue 6): `envshadow render` writes `report.html` unless `--no-report`,
//! `envshadow report DIR` rebuilds it; every picture the page references exists and decodes,
//! and the page loads in headless Chromium with no console errors (skipped with a notice where
//! Chromium is not installed; on CI a failure).

use crate::common::{self, Failures};

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

fn tiny_spec(dir: &Path, validate: bool) -> (PathBuf, PathBuf) {
    let out = dir.join(if validate { "out-validated" } else { "out" });
    let spec = dir.join(if validate {
        "anim-validated.toml"
    } else {
        "anim.toml"
    });
    fs::write(
        &spec,
        format!(
            "[scene]\nbuiltin = \"shapes\"\n[lights]\ncount = 20\n[motion]\nframes = 3\n\
             [render]\nwidth = 48\nheight = 36\ntile = 16\nvalidate = {validate}\n\
             [output]\ndir = \"{}\"\n",
            out.display()
        ),
    )
    .unwrap();
    (spec, out)
}

fn render(spec: &Path, extra: &[&str]) {
    let o = common::bin()
        .arg("render")
        .arg(spec)
        .arg("-q")
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Every `src="…"` and `href="…"` value in the page.
fn references(html: &str) -> Vec<String> {
    let mut refs = Vec::new();
    for attr in ["src=\"", "href=\""] {
        let mut rest = html;
        while let Some(i) = rest.find(attr) {
            rest = &rest[i + attr.len()..];
            let end = rest.find('"').expect("unterminated attribute");
            refs.push(rest[..end].to_string());
            rest = &rest[end..];
        }
    }
    refs
}

/// Checks that every file the page references is local, exists and decodes as an image;
/// returns the references.
fn check_references(dir: &Path, html: &str) -> Vec<String> {
    let refs = references(html);
    assert!(!refs.is_empty(), "the page references no file");
    for r in &refs {
        assert!(
            !r.contains("://") && !r.starts_with("//") && !r.starts_with('/'),
            "{r}: the page must reference only files beside it"
        );
        let path = dir.join(r);
        assert!(path.is_file(), "{r} is referenced but missing");
        if r.ends_with(".mp4") {
            assert!(fs::metadata(&path).unwrap().len() > 0, "{r} is empty");
            continue;
        }
        let img = image::open(&path).unwrap_or_else(|e| panic!("{r} does not decode: {e}"));
        assert!(img.width() > 0 && img.height() > 0, "{r} is empty");
    }
    refs
}

fn gif_frames(path: &Path) -> usize {
    use image::AnimationDecoder;
    let f = std::io::BufReader::new(fs::File::open(path).unwrap());
    let dec = image::codecs::gif::GifDecoder::new(f).unwrap();
    dec.into_frames().collect_frames().unwrap().len()
}

/// Headless Chromium, offline, on `page` with its own `profile`; the caller adds what to do.
fn chromium(page: &Path, profile: &Path) -> Command {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let mut c = Command::new("chromium");
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--no-first-run",
    ])
    .arg(format!("--user-data-dir={}", profile.display()))
    .arg(url);
    c
}

/// A 1280×900 screenshot of `page` in headless Chromium, into `png`.
fn chromium_screenshot(page: &Path, profile: &Path, png: &Path) {
    let o = chromium(page, profile)
        .args(["--hide-scrollbars", "--window-size=1280,900"])
        .arg(format!("--screenshot={}", png.display()))
        .output()
        .expect("running chromium");
    assert!(
        o.status.success() && png.is_file(),
        "no screenshot: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Where `needle` first appears in the page.
fn at(html: &str, needle: &str) -> usize {
    html.find(needle)
        .unwrap_or_else(|| panic!("{needle} not in the page"))
}

/// The page leads with the animation, the totals, the savings plot and the numbered contact
/// sheet, then the lights, and keeps the per-frame detail collapsed.
fn check_structure(html: &str, frames: usize) {
    let animation = html
        .find("report/turntable.gif")
        .or_else(|| html.find("<video"))
        .expect("no animation");
    let order = [
        animation,
        at(html, "shadow rays traced"),
        at(html, "report/plot_percent.png"),
        at(html, "class=\"sheet\""),
        at(html, "report/lights.png"),
        at(html, "<details>"),
        at(html, "report/rays_0000.jpg"),
    ];
    assert!(
        order.windows(2).all(|w| w[0] < w[1]),
        "the page's parts are out of order: {order:?}"
    );
    // Every frame on the contact sheet, with its number.
    let sheet = &html[at(html, "class=\"sheet\"")..at(html, "report/lights.png")];
    for f in 0..frames {
        assert!(
            sheet.contains(&format!("<figcaption>{f}</figcaption>")),
            "frame {f} has no number on the contact sheet"
        );
    }
    // The per-frame detail is collapsed, its pictures loaded only when opened.
    let detail = &html[at(html, "Per-frame detail")..];
    assert!(!html.contains("<details open"), "a section is open");
    assert!(
        detail.contains("loading=\"lazy\""),
        "the heat maps load eagerly"
    );
}

/// Loads `page` in headless Chromium (found on PATH); returns (exit success, DOM, console
/// messages).
fn chromium_load(page: &Path, profile: &Path) -> (bool, String, Vec<String>) {
    let o = chromium(page, profile)
        .args(["--enable-logging=stderr", "--v=0", "--dump-dom"])
        .output()
        .expect("running chromium");
    let stderr = String::from_utf8_lossy(&o.stderr);
    // Chromium logs the page's console messages (including uncaught exceptions) as
    // `[pid:tid:time:INFO:CONSOLE:line] "message", source: url (line)`.
    let console = stderr
        .lines()
        .filter(|l| l.contains(":CONSOLE") || l.contains("Uncaught"))
        .map(str::to_string)
        .collect();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        console,
    )
}

/// Renders the tiny animation (validated or not) into `dir`, then deletes the report `render`
/// wrote and rebuilds it with `envshadow report`; returns the output folder and the page.
fn rebuilt_report(dir: &Path, validate: bool) -> (PathBuf, PathBuf) {
    let (spec, out) = tiny_spec(dir, validate);
    let extra: &[&str] = if validate { &["--validate"] } else { &[] };
    render(&spec, extra);
    let page = out.join("report.html");
    assert!(page.is_file(), "render did not write {}", page.display());
    fs::remove_file(&page).unwrap();
    fs::remove_dir_all(out.join("report")).unwrap();
    let o = common::bin().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (out, page)
}

#[test]
fn report_pages_reference_only_local_images_that_decode() {
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Failures::new();
    for validate in [false, true] {
        failures.case(&format!("validate = {validate}"), || {
            let (out, page) = rebuilt_report(tmp.path(), validate);
            let html = fs::read_to_string(&page).unwrap();
            assert!(!html.contains("<script"), "the page needs no JavaScript");
            let refs = check_references(&out, &html);
            for must in [
                "report/thumb_0000.jpg",
                "report/thumb_0002.jpg",
                "report/turntable.gif",
                "report/plot_percent.png",
                "report/plot_rays_per_pixel.png",
                "report/plot_seconds.png",
                "report/scale_rays.png",
                "report/rays_0000.jpg",
                "report/rays_0002.jpg",
                "report/lights.png",
                "frame_0001.png",
            ] {
                assert!(refs.iter().any(|r| r == must), "{must} not in the page");
            }
            check_structure(&html, 3);
            for validated_only in [
                "report/plot_error.png",
                "report/wrong_0000.png",
                "report/scale_wrong.png",
            ] {
                assert_eq!(
                    refs.iter().any(|r| r == validated_only),
                    validate,
                    "{validated_only} (validate = {validate})"
                );
            }
            assert_eq!(gif_frames(&out.join("report/turntable.gif")), 3);
            let rays_map = image::open(out.join("report/rays_0000.jpg")).unwrap();
            assert_eq!((rays_map.width(), rays_map.height()), (48, 36));
            assert!(html.contains("grid-nowarp-uncertainty") && html.contains("48×36"));
            assert!(
                !html.contains("samples per pixel"),
                "one sample per pixel is the plain resolution"
            );
            assert!(html.contains("shadow rays per second"));
        });
    }
    failures.assert_none();
}

#[test]
fn report_pages_load_in_chromium_without_console_errors() {
    if !common::require_tools(
        common::this_test!(),
        &["chromium"],
        "apt-get install chromium",
    ) {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    // The console check must be able to fail: a page with a script error and a console
    // message is caught.
    let broken = tmp.path().join("broken.html");
    fs::write(
        &broken,
        "<!DOCTYPE html><html><head><title>broken</title></head><body>\
         <script>console.error('deliberate'); no_such_function();</script></body></html>",
    )
    .unwrap();
    let (ok, _, console) = chromium_load(&broken, &tmp.path().join("profile-broken"));
    assert!(ok, "chromium failed on the broken page");
    assert!(
        console.iter().any(|l| l.contains("deliberate"))
            && console.iter().any(|l| l.contains("Uncaught")),
        "the console check does not see a broken page's errors: {console:?}"
    );
    let mut failures = Failures::new();
    for validate in [false, true] {
        failures.case(&format!("validate = {validate}"), || {
            let (_, page) = rebuilt_report(tmp.path(), validate);
            let profile = tmp.path().join(format!("profile-{validate}"));
            let (ok, dom, console) = chromium_load(&page, &profile);
            assert!(ok, "chromium failed to load {}", page.display());
            assert!(
                dom.contains("<title>envshadow report: out"),
                "the DOM lacks the page title:\n{}",
                &dom[..dom.len().min(500)]
            );
            assert!(dom.contains("report/turntable.gif"));
            assert!(console.is_empty(), "console messages: {console:?}");
            // What a person sees first: the animation and the totals fill the first screen.
            let shot = tmp.path().join(format!("top-{validate}.png"));
            chromium_screenshot(&page, &tmp.path().join(format!("shot-{validate}")), &shot);
            let img = image::open(&shot).unwrap().to_rgb8();
            let painted = img
                .pixels()
                .filter(|p| p.0.iter().any(|&c| c < 200))
                .count();
            let share = painted as f64 / (img.width() * img.height()) as f64;
            assert!(
                share > 0.15,
                "the first screen is mostly empty ({:.1} % painted)",
                100.0 * share
            );
        });
    }
    failures.assert_none();
}

#[test]
fn report_names_the_samples_per_pixel_beside_the_resolution() {
    let tmp = tempfile::tempdir().unwrap();
    let (spec, out) = tiny_spec(tmp.path(), false);
    render(&spec, &["--spp", "4"]);
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    let lead = &html[at(&html, "class=\"lead\"")..];
    assert!(
        lead.starts_with("class=\"lead\">3 frames at 48×36 (4 samples per pixel), 20 lights"),
        "{}",
        &lead[..lead.find("</p>").unwrap_or(lead.len())]
    );
}

#[test]
fn render_with_no_report_writes_none() {
    let tmp = tempfile::tempdir().unwrap();
    let (spec, out) = tiny_spec(tmp.path(), false);
    render(&spec, &["--frames", "0", "--no-report"]);
    assert!(out.join("frame_0000.exr").is_file());
    assert!(!out.join("report.html").exists());
    assert!(!out.join("report").exists());
}

#[test]
fn report_without_stats_exits_2_naming_the_path() {
    let tmp = tempfile::tempdir().unwrap();
    let stats = tmp.path().join("stats.csv");
    let o = common::bin()
        .arg("report")
        .arg(tmp.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(&stats.display().to_string()), "{err}");
    assert!(!tmp.path().join("report.html").exists());

    let missing = tmp.path().join("no-such-render");
    let o = common::bin().arg("report").arg(&missing).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains(&missing.display().to_string()), "{err}");

    fs::write(&stats, "frame,method\n").unwrap();
    let o = common::bin()
        .arg("report")
        .arg(tmp.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("stats.csv"), "{err}");
}

#[test]
fn report_sets_the_papers_figure_beside_ours_and_says_when_the_map_is_gone() {
    let tmp = tempfile::tempdir().unwrap();
    let (spec, _) = tiny_spec(tmp.path(), false);
    let out = tmp.path().join("shapes-tiny");
    let out_arg = out.display().to_string();
    render(
        &spec,
        &["--frames", "0", "--lights", "50", "--out", &out_arg],
    );
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    // Table 1, shapes scene, 50 lights, grid-nowarp-uncertainty: 9.4 %.
    assert!(html.contains("Beside the paper"), "no paper figure");
    assert!(html.contains("<td>9.4</td>"), "wrong paper figure");
    assert!(html.contains("src=\"report/lights.png\""));

    // The environment map named in lights.json cannot be found: the page says so.
    let json = out.join("lights.json");
    let text = fs::read_to_string(&json).unwrap();
    assert!(text.contains("builtin:sky"));
    fs::write(&json, text.replace("builtin:sky", "nowhere/missing.hdr")).unwrap();
    fs::remove_dir_all(out.join("report")).unwrap();
    let o = common::bin().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("No picture of the lights"), "{html}");
    assert!(html.contains("nowhere/missing.hdr"));
    check_references(&out, &html);
}

/// The heat maps' colour scales come from the frame records (no EXR decoded for them) when the
/// files are the recorded ones; a folder whose records do not carry the figures (an earlier
/// version's) gets the very same maps from the EXRs.
#[test]
fn report_scales_from_the_records_match_those_from_the_exrs() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, _) = rebuilt_report(tmp.path(), true);
    let maps = ["rays_0000.jpg", "rays_0002.jpg", "wrong_0001.png"];
    let read = |out: &Path| -> Vec<Vec<u8>> {
        maps.iter()
            .map(|m| fs::read(out.join("report").join(m)).unwrap())
            .collect()
    };
    let from_records = read(&out);
    let record = out.join("records/frame_0001.json");
    let text = fs::read_to_string(&record).unwrap();
    assert!(text.contains("\"rays_histogram\": \"0:"), "{text}");
    assert!(text.contains("\"wrong_max\": "), "{text}");
    let edit = |f: usize, change: &dyn Fn(&mut serde_json::Map<String, serde_json::Value>)| {
        let path = out.join(format!("records/frame_{f:04}.json"));
        let mut v: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
        change(v.as_object_mut().unwrap());
        fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    };
    // The records are what the scale is read from: a record saying most pixels traced 1000
    // rays darkens every map.
    let saved = fs::read(&record).unwrap();
    edit(1, &|o| {
        o.insert("rays_histogram".into(), "0:1 1000:100000".into());
    });
    let o = common::bin().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        read(&out)[0] != from_records[0],
        "the record's histogram was not read"
    );
    fs::write(&record, saved).unwrap();
    for f in 0..3 {
        edit(f, &|o| {
            o.remove("rays_histogram");
            o.remove("wrong_max");
        });
    }
    let o = common::bin().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        from_records == read(&out),
        "the maps differ without the records' figures"
    );
}

/// An EXR of the recorded size that does not decode is named on its frame; the report is
/// still written.
#[test]
fn report_names_an_unreadable_exr_its_record_vouched_for() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, _) = rebuilt_report(tmp.path(), false);
    let exr = out.join("frame_0001.exr");
    let len = fs::metadata(&exr).unwrap().len() as usize;
    fs::write(&exr, vec![0u8; len]).unwrap();
    let o = common::bin().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("frame_0001.exr") && html.contains("not a readable EXR"),
        "the page does not name the bad EXR"
    );
    assert!(!out.join("report/rays_0001.jpg").exists());
    assert!(out.join("report/rays_0002.jpg").is_file());
}
