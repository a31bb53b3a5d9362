//! `holoc render SCENE.holo -o plan.svg`: build the scene and draw its plan; with `--3d`, write
//! the 3D viewer page of `holoc view` instead.

use super::common::{self, ColorChoice, DiagFormat};
use crate::solve::Solver;
use crate::source::SourceMap;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `holoc render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The `.holo` scene.
    pub file: PathBuf,
    /// Where to write the SVG (or the HTML page with `--3d`; stdout when absent or `-`); written
    /// atomically.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Overrides the scene's seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// The floor solver.
    #[arg(long, value_enum, default_value_t = super::build::SolverArg::Dfs)]
    pub solver: super::build::SolverArg,
    /// User asset catalogs.
    #[command(flatten)]
    pub catalogs: super::assets::CatalogArgs,
    /// Leave out things the catalog lacks instead of letting stand-ins fill in (W0403).
    #[arg(long)]
    pub no_stand_ins: bool,
    /// The radius of the agent (metres) the layout leaves room for (default 0.25).
    #[arg(long, value_name = "METRES", value_parser = super::build::parse_radius)]
    pub agent_radius: Option<f64>,
    /// Write the 3D viewer page (HTML, as `holoc view` makes it) instead of the SVG plan.
    #[arg(long = "3d")]
    pub three_d: bool,
    /// With `--3d`: what to draw.
    #[command(flatten)]
    pub draw: super::export::DrawArgs,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = DiagFormat::Human)]
    pub format: DiagFormat,
    /// When to colour human diagnostics.
    #[arg(long, value_enum, default_value_t = ColorChoice::Auto)]
    pub color: ColorChoice,
}

/// Runs `holoc render`.
pub fn run(args: &RenderArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let file = match common::read_source(&mut sources, &args.file) {
        Ok(id) => id,
        Err(d) => {
            common::emit_plain(&d);
            return ExitCode::from(2);
        }
    };
    let request = super::build::BuildRequest {
        catalogs: &args.catalogs,
        seed: args.seed,
        add_doors: false,
        solver: match args.solver {
            super::build::SolverArg::Dfs => Solver::Dfs,
            super::build::SolverArg::Milp => Solver::Milp,
        },
        node_budget: None,
        agent_radius_m: args.agent_radius,
        repair: false,
        format: args.format,
        color: args.color,
        stdout_taken: args.output.as_deref().is_none_or(|p| p.as_os_str() == "-"),
        stand_ins: !args.no_stand_ins,
        make: true,
    };
    let (product, catalog, diagnostics) =
        match super::build::run_build(&mut sources, file, &request) {
            Ok(built) => built,
            Err(code) => return code,
        };
    let svg = if args.three_d {
        let made = crate::make::used_in(
            &product.resolved,
            product.objects.iter().map(|o| o.asset_id.as_str()),
        );
        let mut options = args.draw.options(false);
        options.made = std::sync::Arc::new(crate::export::MadeMeshes::of_made(&made));
        let exported =
            match super::export::export_or_report(&product.house.house, &catalog, &options) {
                Ok(e) => e,
                Err(code) => return code,
            };
        let report = crate::report::report(&product, &catalog);
        let title = args.file.file_stem().map_or_else(|| "house".into(), |s| s.to_string_lossy());
        crate::export::viewer::page(&product.house.house, &exported.to_glb(), Some(&report), &title)
    } else {
        crate::render::render_svg(&crate::render::drawing(&product))
    };
    if let Err(d) = common::write_output(args.output.as_deref(), &svg) {
        common::emit_plain(&d);
        return ExitCode::from(2);
    }
    common::exit_for(&diagnostics)
}
