//! `holoc view HOUSE.json -o house.html [--report report.json]`: one self-contained HTML page
//! that shows the house in 3D (see `export/viewer.rs`).

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::{Code, Diagnostic};
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc view`.
#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// The house JSON file (as `holoc build` writes it); with a second house, the house before.
    pub file: PathBuf,
    /// A second house: the page shows it (the house after) with what changed since the first
    /// (moved objects with an arrow from where they stood, added ones green, removed ones red).
    pub after: Option<PathBuf>,
    /// Where to write the HTML page; written atomically.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The build report (`holoc build --report`): a click on an object then shows its relations.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Draw the ceilings too (left out by default, to look in from above).
    #[arg(long)]
    pub ceiling: bool,
    /// What to draw.
    #[command(flatten)]
    pub draw: super::export::DrawArgs,
    /// User asset catalogs: they give the sizes of assets beyond the embedded AI2-THOR catalog.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Reads a build report; E0001 when unreadable, E0004 when not JSON.
#[allow(
    clippy::result_large_err,
    reason = "the error is printed at once; it is rare and never propagated far"
)]
fn read_report(path: &std::path::Path) -> Result<serde_json::Value, Diagnostic> {
    let text = common::read_text(path)?;
    serde_json::from_str(&text).map_err(|e| {
        Diagnostic::new(Code::E0004, format!("`{}` is not a build report: {e}", path.display()))
            .with_help("write it with `holoc build --report FILE`")
    })
}

/// Runs `holoc view`.
pub fn run(args: &ViewArgs) -> ExitCode {
    let report = match args.report.as_deref().map(read_report).transpose() {
        Ok(r) => r,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let shown = args.after.as_deref().unwrap_or(&args.file);
    let loaded = match super::export::load_house(
        shown,
        &args.catalogs,
        args.draw.assets_dir.as_deref(),
        args.format,
        args.color,
    ) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let compare = match &args.after {
        None => None,
        Some(_) => {
            let before = match super::export::load_house(
                &args.file,
                &args.catalogs,
                None,
                args.format,
                args.color,
            ) {
                Ok(l) => l,
                Err(code) => return code,
            };
            let name = args.file.display().to_string();
            Some(changes(&before.house, &loaded.house, &loaded.catalog, &name))
        }
    };
    let mut options = args.draw.options(args.ceiling);
    options.made = std::sync::Arc::new(loaded.made.clone());
    let exported = match super::export::export_or_report(&loaded.house, &loaded.catalog, &options) {
        Ok(e) => e,
        Err(code) => return code,
    };
    let title = shown.file_stem().map_or_else(|| "house".into(), |s| s.to_string_lossy());
    let html = crate::export::viewer::page_with(
        &loaded.house,
        &exported.to_glb(),
        report.as_ref(),
        &title,
        compare.as_ref(),
    );
    if let Err(d) = common::write_atomic(&args.output, html.as_bytes()) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    common::emit_status(&format!(
        "wrote {}: {} objects, {} bytes",
        args.output.display(),
        exported.counts.objects,
        html.len()
    ));
    common::exit_for(&loaded.diagnostics)
}

/// What changed from `before` to `after`, for the before/after page: the objects `holoc diff`
/// finds moved (from and to their centres), added (their ids in `after`) and removed (their
/// centre, size from the catalog, and turn in `before`).
fn changes(
    before: &crate::lower::thor::House,
    after: &crate::lower::thor::House,
    catalog: &crate::resolve::Catalog,
    name: &str,
) -> serde_json::Value {
    use crate::diff::{self, HouseView, Kind};
    use serde_json::json;
    let view = |h: &crate::lower::thor::House| {
        serde_json::to_value(h).ok().and_then(|v| HouseView::read(&v).ok())
    };
    let (Some(a), Some(b)) = (view(before), view(after)) else {
        return json!({"before": name, "moved": [], "added": [], "removed": []});
    };
    let found = diff::diff(&a, &b, &diff::Options::default());
    let find = |v: &HouseView, id: &str| v.objects.iter().find(|o| o.id == id).cloned();
    let (mut moved, mut added, mut removed) = (Vec::new(), Vec::new(), Vec::new());
    for c in &found.changes {
        match c.kind {
            Kind::ObjectMoved => {
                let was = c.was.as_deref().unwrap_or(&c.subject);
                if let (Some(x), Some(y)) = (find(&a, was), find(&b, &c.subject)) {
                    moved.push(json!({"id": c.subject, "from": x.position, "to": y.position}));
                }
            }
            Kind::ObjectAdded => added.push(json!(c.subject)),
            Kind::ObjectRemoved => {
                if let Some(x) = find(&a, &c.subject) {
                    let size = catalog.get(&x.asset).map_or([0.3, 0.3, 0.3], |s| s.bbox_m);
                    removed.push(json!({"id": c.subject, "at": x.position, "size": size,
                        "rotation": x.rotation_deg}));
                }
            }
            _ => {}
        }
    }
    json!({"before": name, "moved": moved, "added": added, "removed": removed})
}
