//! `holoc view HOUSE.json -o house.html [--report report.json]`: one self-contained HTML page
//! that shows the house in 3D (see `export/viewer.rs`).

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::{Code, Diagnostic};
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc view`.
#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// The house JSON file (as `holoc build` writes it).
    pub file: PathBuf,
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
    let loaded = match super::export::load_house(
        &args.file,
        &args.catalogs,
        args.draw.assets_dir.as_deref(),
        args.format,
        args.color,
    ) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let mut options = args.draw.options(args.ceiling);
    options.made = std::sync::Arc::new(loaded.made.clone());
    let exported = match super::export::export_or_report(&loaded.house, &loaded.catalog, &options) {
        Ok(e) => e,
        Err(code) => return code,
    };
    let title = args.file.file_stem().map_or_else(|| "house".into(), |s| s.to_string_lossy());
    let html =
        crate::export::viewer::page(&loaded.house, &exported.to_glb(), report.as_ref(), &title);
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
