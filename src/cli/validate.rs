//! `holoc validate HOUSE.json…`: schema and geometric checks of house files.

use super::common::{self, ColorChoice, DiagFormat};
use crate::resolve::structure::StructureCatalog;
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc validate`.
#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// The house JSON files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// User asset catalogs: they give the sizes of assets beyond the embedded AI2-THOR catalog
    /// for the footprint checks.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// The folder of the assets holoc made for these houses (default: `<house stem>.assets/`
    /// beside each house, when it exists).
    #[arg(long, value_name = "DIR")]
    pub assets_dir: Option<PathBuf>,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc validate`.
pub fn run(args: &ValidateArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let mut diagnostics = Vec::new();
    let mut io_failed = false;
    let loaded = args.catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, args.format, args.color);
        return ExitCode::from(1);
    }
    diagnostics.extend(loaded.diagnostics);
    let catalog = loaded.value;
    if !crate::lower::validate::SCHEMA_CHECKED {
        common::emit_status(
            "note: this holoc was built without its `schema` feature: houses are not checked against \
             the JSON Schema, only against the rules AI2-THOR relies on",
        );
    }
    for path in &args.files {
        match common::read_source(&mut sources, path) {
            Ok(id) => {
                let folder =
                    args.assets_dir.clone().unwrap_or_else(|| crate::make::folder_beside(path));
                let (made, _) = crate::make::read_folder(&folder);
                let with_made = catalog.with_made(made);
                let outcome = crate::lower::validate::validate(
                    &sources,
                    id,
                    StructureCatalog::builtin(),
                    &with_made,
                );
                diagnostics.extend(outcome.diagnostics);
                diagnostics.extend(objathor_on_disk(&sources, id, &catalog));
            }
            Err(d) => {
                common::emit_plain(&d);
                io_failed = true;
            }
        }
    }
    common::emit(&sources, &diagnostics, args.format, args.color);
    if io_failed {
        return ExitCode::from(2);
    }
    common::exit_for(&diagnostics)
}

/// The on-disk check of the objathor assets a house uses (`--objathor`): every `assetId` of its
/// objects and their children, each reported at its first place in the file.
fn objathor_on_disk(
    sources: &SourceMap,
    file: crate::source::FileId,
    catalog: &crate::resolve::Catalog,
) -> Vec<crate::diag::Diagnostic> {
    if catalog.objathor().is_none() {
        return Vec::new();
    }
    let text = &sources.get(file).text;
    let Ok(house) = serde_json::from_str::<serde_json::Value>(text) else { return Vec::new() };
    let mut ids = Vec::new();
    let mut stack: Vec<&serde_json::Value> =
        house.get("objects").and_then(serde_json::Value::as_array).into_iter().flatten().collect();
    while let Some(object) = stack.pop() {
        if let Some(id) = object.get("assetId").and_then(serde_json::Value::as_str) {
            ids.push(id.to_string());
        }
        stack.extend(
            object.get("children").and_then(serde_json::Value::as_array).into_iter().flatten(),
        );
    }
    let span_of = |uid: &str| {
        let start = text.find(&format!("\"{uid}\""))?;
        Some(crate::source::Span::new(file, start, start + uid.len() + 2))
    };
    crate::resolve::objathor::check_on_disk(catalog, ids.iter().map(String::as_str), &span_of)
}
