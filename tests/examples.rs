//! Every example builds: no errors, a house that `holoc validate` accepts, the same bytes twice,
//! and a reviewed snapshot of its layout; the paper's apartment is also kept as a golden house
//! and a golden SVG plan.

mod common;

use holoc::compile::{build, BuildOptions, Built};
use holoc::plan::PlanOptions;
use holoc::resolve::structure::StructureCatalog;
use holoc::resolve::Catalog;
use holoc::solve::Solver;
use holoc::source::SourceMap;
use std::path::{Path, PathBuf};

fn examples() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir("examples")
        .expect("examples folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "holo"))
        .collect();
    out.sort();
    out
}

fn build_example(
    path: &Path,
    solver: Solver,
) -> (SourceMap, Option<Built>, Vec<holoc::diag::Diagnostic>) {
    let mut sources = SourceMap::new();
    let id =
        sources.add(path.display().to_string(), std::fs::read_to_string(path).expect("readable"));
    let catalog = Catalog::embedded();
    let options = BuildOptions {
        seed: None,
        plan: PlanOptions::default(),
        catalog: &catalog,
        solver,
        node_budget: None,
    };
    let out = build(&sources, id, &options);
    (sources, out.value, out.diagnostics)
}

#[test]
fn every_example_builds_validates_and_is_deterministic() {
    for path in examples() {
        for solver in [Solver::Dfs, Solver::Milp] {
            let (sources, built, diagnostics) = build_example(&path, solver);
            let Some(built) = built else {
                panic!(
                    "{} does not build:\n{}",
                    path.display(),
                    common::render(&sources, &diagnostics)
                );
            };
            let json = built.house.to_json_string();
            let (_, again, _) = build_example(&path, solver);
            assert_eq!(
                again.expect("builds again").house.to_json_string(),
                json,
                "{}: not deterministic",
                path.display()
            );
            let mut house_sources = SourceMap::new();
            let house = house_sources.add("house.json", json);
            let validated = holoc::lower::validate::validate(
                &house_sources,
                house,
                StructureCatalog::builtin(),
                &Catalog::embedded(),
            );
            // No errors, and none of the footprint warnings: every floor object stays in its
            // room and no two overlap, judged by `holoc validate` from the house file alone.
            let errors: Vec<_> = validated
                .diagnostics
                .iter()
                .filter(|d| d.is_error() || matches!(d.code.as_str(), "W0608" | "W0609"))
                .cloned()
                .collect();
            assert!(
                errors.is_empty(),
                "{}: validate rejects the house:\n{}",
                path.display(),
                common::render(&house_sources, &errors)
            );
            // Every floor object is in its room and no two footprints overlap.
            for solved in &built.layout.rooms {
                let floor = &solved.layout.floor;
                for (i, a) in floor.iter().enumerate() {
                    for b in &floor[i + 1..] {
                        let (fa, fb) = (a.footprint, b.footprint);
                        let overlap_x = fa.max_x.min(fb.max_x) - fa.min_x.max(fb.min_x);
                        let overlap_z = fa.max_z.min(fb.max_z) - fa.min_z.max(fb.min_z);
                        assert!(
                            overlap_x <= 1e-6 || overlap_z <= 1e-6,
                            "{}: {} and {} overlap",
                            path.display(),
                            solved.problem.objects[a.index].id,
                            solved.problem.objects[b.index].id
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn example_layouts() {
    insta::with_settings!({snapshot_path => "../snapshots/examples", prepend_module_to_snapshot => false, omit_expression => true}, {
        for path in examples() {
            let (sources, built, diagnostics) = build_example(&path, Solver::Dfs);
            let built = built.expect("builds");
            let name = path.file_stem().expect("file name").to_string_lossy().to_string();
            let body = format!(
                "----- DIAGNOSTICS\n{}----- LAYOUT\n{}",
                common::render(&sources, &diagnostics),
                built.layout.dump(&built.scene)
            );
            insta::assert_snapshot!(format!("layout_{name}"), body);
        }
    });
}

#[test]
fn golden_apartment_house_and_plan() {
    let (_, built, _) = build_example(Path::new("examples/apartment_1b1b.holo"), Solver::Dfs);
    let built = built.expect("builds");
    insta::with_settings!({snapshot_path => "../snapshots/examples", prepend_module_to_snapshot => false, omit_expression => true}, {
        insta::assert_snapshot!("golden_apartment_house", built.house.to_json_string());
        insta::assert_snapshot!("golden_apartment_plan_svg", holoc::render::render_svg(&holoc::render::drawing(&built)));
    });
}
