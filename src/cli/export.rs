//! `holoc export HOUSE.json -o house.glb`: a house as glTF 2.0 binary (see `export/`).

use super::common::{self, ColorChoice, DiagFormat};
use crate::diag::{Code, Diagnostic};
use crate::export::{ExportError, ExportOptions, ObjectMode};
use crate::lower::thor::House;
use crate::resolve::structure::StructureCatalog;
use crate::resolve::Catalog;
use crate::source::SourceMap;
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::ExitCode;

/// What to draw, shared by `export`, `view`, `build --emit glb` and `render --3d`.
#[derive(Debug, Clone, clap::Args)]
pub struct DrawArgs {
    /// Only these rooms (ids, comma-separated), with their walls, windows, objects and the
    /// doors that touch them.
    #[arg(long, value_delimiter = ',', value_name = "ROOM,…")]
    pub rooms: Vec<String>,
    /// How objects are drawn: as their asset's bounding box, or not at all.
    #[arg(long, value_enum, default_value_t = ObjectMode::Boxes)]
    pub objects: ObjectMode,
    /// The folder of the assets holoc made for the house (default: `<house stem>.assets/`
    /// beside it): they are drawn with their parts and colours.
    #[arg(long, value_name = "DIR")]
    pub assets_dir: Option<PathBuf>,
}

impl DrawArgs {
    /// The export options, with or without ceilings.
    pub fn options(&self, ceiling: bool) -> ExportOptions {
        ExportOptions {
            ceiling,
            rooms: (!self.rooms.is_empty())
                .then(|| self.rooms.iter().cloned().collect::<BTreeSet<_>>()),
            objects: self.objects,
            made: std::sync::Arc::default(),
        }
    }
}

/// Arguments of `holoc export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// The house JSON file (as `holoc build` writes it).
    pub file: PathBuf,
    /// Where to write the `.glb` file; written atomically.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Leave out the ceilings (the default of `holoc view`).
    #[arg(long)]
    pub no_ceiling: bool,
    /// What to draw.
    #[command(flatten)]
    pub draw: DrawArgs,
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

/// A house read from a file and checked by `holoc validate`'s rules, with the catalog that
/// gives its objects' sizes.
pub(crate) struct LoadedHouse {
    pub house: House,
    pub catalog: Catalog,
    pub diagnostics: Vec<Diagnostic>,
    /// The meshes of the made assets it uses, read from their folder.
    pub made: crate::export::MadeMeshes,
}

/// Reads and validates a house file; prints its diagnostics. Errors give the exit code.
pub(crate) fn load_house(
    path: &std::path::Path,
    catalogs: &super::assets::CatalogArgs,
    assets_dir: Option<&std::path::Path>,
    format: DiagFormat,
    color: ColorChoice,
) -> Result<LoadedHouse, ExitCode> {
    let mut sources = SourceMap::new();
    let loaded = catalogs.load(&mut sources);
    if loaded.has_errors() {
        common::emit(&sources, &loaded.diagnostics, format, color);
        return Err(ExitCode::from(1));
    }
    let mut diagnostics = loaded.diagnostics;
    // The assets holoc made for it, from their folder: known to the checks by their boxes.
    let folder =
        assets_dir.map_or_else(|| crate::make::folder_beside(path), std::path::Path::to_path_buf);
    // Read once: their boxes for the checks, their meshes for the drawing.
    let (made_assets, _, reads) = crate::make::read_folder_assets(&folder);
    let catalog = loaded.value.with_made(made_assets);
    let made = crate::export::MadeMeshes::of_read(&reads);
    let file = match common::read_source(&mut sources, path) {
        Ok(id) => id,
        Err(d) => {
            common::emit_plain(&d);
            return Err(ExitCode::from(2));
        }
    };
    let checked =
        crate::lower::validate::validate(&sources, file, StructureCatalog::builtin(), &catalog);
    diagnostics.extend(checked.diagnostics);
    let house = if diagnostics.iter().any(Diagnostic::is_error) {
        None
    } else {
        // What AI2-THOR fills with its defaults (a ProcTHOR house's missing agent, layers,
        // openable doors…) is filled the same way before the house is read.
        let read = serde_json::from_str::<serde_json::Value>(&sources.get(file).text)
            .map(|mut value| {
                crate::export::defaults::fill(&mut value);
                value
            })
            .and_then(serde_json::from_value::<House>);
        match read {
            Ok(h) => Some(h),
            Err(e) => {
                diagnostics.push(
                    Diagnostic::new(
                        Code::E0616,
                        format!("`{}` lacks what a house needs to be drawn: {e}", path.display()),
                    )
                    .with_primary(
                        crate::source::Span::new(file, 0, 0),
                        "no default can stand in for it",
                    )
                    .with_help(
                        "give the member it names (AI2-THOR has no default for it), or write \
                         the house with `holoc build`",
                    ),
                );
                None
            }
        }
    };
    common::emit(&sources, &diagnostics, format, color);
    match house {
        Some(house) => Ok(LoadedHouse { house, catalog, diagnostics, made }),
        None => Err(common::exit_for(&diagnostics)),
    }
}

/// Exports, printing why not (E0004 for `--rooms` naming no room) on failure.
pub(crate) fn export_or_report(
    house: &House,
    catalog: &Catalog,
    options: &ExportOptions,
) -> Result<crate::export::Export, ExitCode> {
    crate::export::export(house, catalog, options).map_err(|e| {
        match e {
            ExportError::UnknownRooms { unknown, known } => {
                let close =
                    crate::diag::suggest::closest(&unknown[0], known.iter().map(String::as_str));
                let help = crate::diag::suggest::did_you_mean(&close)
                    .unwrap_or_else(|| format!("the house's rooms: {}", known.join(", ")));
                common::emit_plain(
                    &Diagnostic::new(
                        Code::E0004,
                        format!("`--rooms`: the house has no room `{}`", unknown.join("`, `")),
                    )
                    .with_help(help),
                );
            }
        }
        ExitCode::from(2)
    })
}

/// Runs `holoc export`.
pub fn run(args: &ExportArgs) -> ExitCode {
    let loaded = match load_house(
        &args.file,
        &args.catalogs,
        args.draw.assets_dir.as_deref(),
        args.format,
        args.color,
    ) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let mut options = args.draw.options(!args.no_ceiling);
    options.made = std::sync::Arc::new(loaded.made.clone());
    let exported = match export_or_report(&loaded.house, &loaded.catalog, &options) {
        Ok(e) => e,
        Err(code) => return code,
    };
    let glb = exported.to_glb();
    if let Err(d) = common::write_atomic(&args.output, &glb) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    common::emit_status(&format!(
        "exported {}: {}, {} bytes",
        args.output.display(),
        exported.counts,
        glb.len()
    ));
    common::exit_for(&loaded.diagnostics)
}
