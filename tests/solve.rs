//! Integration tests of the `solve` stage over the layout corpus (`tests/corpus/solve/`).

#[path = "support/solve_corpus.rs"]
mod solve_corpus;

use std::fmt::Write as _;

use holoc::check::scene::{GlobalKind, RelationKind};
use holoc::diag::Code;
use holoc::solve::{
    self, FloorObject, ProblemConstraint, Role, RoomLayout, RoomProblem, SmallObject, SolveOptions,
    Solver,
};
use proptest::prelude::*;

/// The layout as text with fixed precision, for snapshots.
fn dump(problem: &RoomProblem, layout: &RoomLayout) -> String {
    let mut s = String::new();
    let (ok, total) = layout.constraint_tally(problem);
    let _ =
        writeln!(s, "room {}: {ok}/{total} constraints, score {:.3}", problem.name, layout.score);
    for p in &layout.floor {
        let o = &problem.objects[p.index];
        let _ = writeln!(
            s,
            "floor {} at ({:.3}, {:.3}) rot {} by {} score {:.3}",
            o.id,
            p.pose.x,
            p.pose.z,
            p.pose.rot.deg(),
            p.by,
            p.score
        );
        for c in &p.constraints {
            let _ = writeln!(
                s,
                "  {} {} {:.3} {}",
                if c.measure.satisfied { "ok  " } else { "FAIL" },
                c.text,
                (c.measure.value * 1000.0).round() / 1000.0 + 0.0, // no `-0.000`
                c.measure.unit
            );
        }
    }
    for (kind, list) in [("wall", &layout.wall), ("small", &layout.small)] {
        for p in list {
            let [x, y, z] = p.position_m;
            let _ =
                writeln!(s, "{kind} {} at ({x:.3}, {y:.3}, {z:.3}) rot {}", p.id, p.rotation_deg);
        }
    }
    if let Some(c) = &layout.ceiling {
        let [x, y, z] = c.position_m;
        let _ = writeln!(s, "ceiling {} at ({x:.3}, {y:.3}, {z:.3})", c.id);
    }
    for u in &layout.unplaced {
        let _ = writeln!(s, "unplaced {} {}: {}", u.kind, u.id, u.reason);
    }
    s
}

fn check_hard_rules(problem: &RoomProblem, layout: &RoomLayout) {
    let room = solve::RoomShape::new(&problem.outline).expect("corpus rooms are valid");
    for (i, a) in layout.floor.iter().enumerate() {
        assert!(
            room.contains_rect(&a.footprint),
            "{}: {} outside",
            problem.name,
            problem.objects[a.index].id
        );
        for b in &layout.floor[i + 1..] {
            assert!(
                !a.footprint.overlaps(&b.footprint),
                "{}: {} overlaps {}",
                problem.name,
                problem.objects[a.index].id,
                problem.objects[b.index].id
            );
        }
        for k in &problem.keep_out {
            let r = solve::Rect::bounding(k);
            assert!(
                !a.footprint.overlaps(&r),
                "{}: {} in a door zone",
                problem.name,
                problem.objects[a.index].id
            );
        }
        // `edge` is soft: an edge object no wall pose could take stands elsewhere, reported.
        assert!(
            a.constraints[0].measure.satisfied
                || problem.objects[a.index].global == GlobalKind::Edge,
            "{}: global broken",
            problem.name
        );
    }
}

/// Every placed object's use-clearance is free of the furniture it does not let in (its front
/// zones inside the room); a bed's (one long side open) only when `beds`: the MILP does not
/// express that choice of two zones.
fn check_use_clearances(problem: &RoomProblem, layout: &RoomLayout, beds: bool) {
    let room = solve::RoomShape::new(&problem.outline).expect("corpus rooms are valid");
    let related = |a: usize, b: usize| {
        problem.objects[a].constraints.iter().any(|x| x.target == b)
            || problem.objects[b].constraints.iter().any(|x| x.target == a)
    };
    for p in &layout.floor {
        let o = &problem.objects[p.index];
        let (zones, all) = solve::use_zones_of(problem, p.index, &p.pose);
        if zones.is_empty() || (!all && !beds) {
            continue;
        }
        let free = |z: &solve::Rect| {
            room.contains_rect(z)
                && layout.floor.iter().all(|q| {
                    q.index == p.index
                        || o.role.lets_in(problem.objects[q.index].role, related(p.index, q.index))
                        || !q.footprint.overlaps(z)
                })
        };
        let kept = if all { zones.iter().all(free) } else { zones.iter().any(free) };
        assert!(kept, "{}: the use-clearance of {} is not free", problem.name, o.id);
    }
}

#[test]
fn corpus_layouts_snapshot_and_keep_hard_rules() {
    for (name, problem) in solve_corpus::load_all() {
        let out = solve::solve_room(&problem, &SolveOptions::default());
        assert!(!out.has_errors(), "{name}: {:?}", out.diagnostics);
        check_hard_rules(&problem, &out.value);
        check_use_clearances(&problem, &out.value, true);
        insta::with_settings!({snapshot_path => "../snapshots/solve", prepend_module_to_snapshot => false}, {
            insta::assert_snapshot!(format!("dfs_{name}"), dump(&problem, &out.value));
        });
    }
}

#[test]
fn milp_layouts_keep_hard_rules() {
    for (name, problem) in solve_corpus::load_all() {
        if problem.objects.len() > 14 {
            continue; // the big rooms are covered by the benchmark
        }
        let opts = SolveOptions { solver: Solver::Milp, ..SolveOptions::default() };
        let out = solve::solve_room(&problem, &opts);
        assert!(!out.has_errors(), "{name}: {:?}", out.diagnostics);
        check_hard_rules(&problem, &out.value);
        check_use_clearances(&problem, &out.value, false);
        // Each MILP back end has its own snapshots: where several poses are equally good, HiGHS
        // and microlp may return different ones (deterministically).
        let backend = if cfg!(feature = "highs") { "milp_highs" } else { "milp" };
        insta::with_settings!({snapshot_path => "../snapshots/solve", prepend_module_to_snapshot => false}, {
            insta::assert_snapshot!(format!("{backend}_{name}"), dump(&problem, &out.value));
        });
    }
}

#[test]
fn same_seed_same_layout_byte_for_byte() {
    for (_, problem) in solve_corpus::load_all().into_iter().take(8) {
        let opts = SolveOptions { seed: 7, ..SolveOptions::default() };
        let a = dump(&problem, &solve::solve_room(&problem, &opts).value);
        let b = dump(&problem, &solve::solve_room(&problem, &opts).value);
        assert_eq!(a, b);
    }
}

#[test]
fn infeasible_objects_are_reported_and_the_rest_placed() {
    let path = solve_corpus::corpus_dir().join("infeasible.json");
    let problem = solve_corpus::load(&path);
    let out = solve::solve_room(&problem, &SolveOptions::default());
    let layout = &out.value;
    assert!(layout.unplaced.iter().any(|u| u.id == "bed-0"));
    assert!(
        layout.floor.iter().any(|p| problem.objects[p.index].id == "plant-0"),
        "later objects still placed"
    );
    assert!(out.diagnostics.iter().any(|d| d.code == Code::W0501 && d.message.contains("bed-0")));
}

#[test]
fn middle_is_enforced() {
    for (_, problem) in solve_corpus::load_all() {
        let out = solve::solve_room(&problem, &SolveOptions::default());
        let room = solve::RoomShape::new(&problem.outline).expect("valid");
        for p in &out.value.floor {
            if problem.objects[p.index].global == GlobalKind::Middle {
                assert!(room.contains_rect(&p.footprint.grow(solve::constraints::MIDDLE_GAP_M)));
            }
        }
    }
}

#[test]
fn doors_are_never_boxed_in() {
    // A room 3 m deep with a door at the south: a wall of cabinets across the room would cut
    // the north half off; the solver must keep everything reachable.
    let mut objects = Vec::new();
    for k in 0..8 {
        objects.push(FloorObject {
            id: format!("cabinet-{k}"),
            size: [1.0, 0.6],
            height: 1.2,
            global: GlobalKind::Middle,
            role: holoc::solve::Role::Other,
            constraints: if k == 0 {
                Vec::new()
            } else {
                vec![ProblemConstraint {
                    kind: RelationKind::Near,
                    written: RelationKind::Near,
                    implied: false,
                    target: k - 1,
                    span: None,
                }]
            },
            pin: None,
            thor_type: None,
            span: None,
        });
    }
    let problem = RoomProblem {
        name: "corridor".into(),
        outline: vec![[0.0, 0.0], [0.0, 4.0], [3.0, 4.0], [3.0, 0.0]],
        wall_height: 2.7,
        keep_out: vec![vec![[1.0, 0.0], [1.0, 1.0], [2.0, 1.0], [2.0, 0.0]]],
        walls: Vec::new(),
        objects,
        wall_objects: Vec::new(),
        small_objects: Vec::new(),
        ceiling: None,
        span: None,
    };
    let out = solve::solve_room(&problem, &SolveOptions::default());
    let room = solve::RoomShape::new(&problem.outline).expect("valid");
    let grid = solve::constraints::ReachGrid::new(
        &room,
        &[solve::Rect::bounding(&problem.keep_out[0])],
        0.25,
    );
    let fps: Vec<_> = out.value.floor.iter().map(|p| p.footprint).collect();
    assert!(grid.unreachable(&fps).is_empty());
    assert!(grid.ok(&fps));
}

fn random_problem(sizes: Vec<(f64, f64, bool)>, w: f64, d: f64) -> RoomProblem {
    let objects = sizes
        .iter()
        .enumerate()
        .map(|(k, &(sw, sd, middle))| FloorObject {
            id: format!("obj-{k}"),
            size: [sw, sd],
            height: 0.8,
            global: if middle { GlobalKind::Middle } else { GlobalKind::Edge },
            role: holoc::solve::Role::Other,
            constraints: if k == 0 {
                Vec::new()
            } else {
                vec![ProblemConstraint {
                    kind: RelationKind::Near,
                    written: RelationKind::Near,
                    implied: false,
                    target: k - 1,
                    span: None,
                }]
            },
            pin: None,
            thor_type: None,
            span: None,
        })
        .collect();
    RoomProblem {
        name: "random".into(),
        outline: vec![
            [0.0, 0.0],
            [0.0, d],
            [w, d],
            [w, d / 2.0],
            [w / 2.0, d / 2.0],
            [w / 2.0, 0.0],
        ],
        wall_height: 2.7,
        keep_out: vec![vec![[0.0, 0.0], [0.0, 0.9], [0.9, 0.9], [0.9, 0.0]]],
        walls: Vec::new(),
        objects,
        wall_objects: Vec::new(),
        small_objects: Vec::new(),
        ceiling: None,
        span: None,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, rng_seed: proptest::test_runner::RngSeed::Fixed(0x686f_6c6f), ..ProptestConfig::default() })]
    #[test]
    fn placed_footprints_never_overlap_and_stay_inside(
        sizes in prop::collection::vec((0.3f64..2.0, 0.3f64..1.5, any::<bool>()), 1..8),
        w in 3.0f64..7.0,
        d in 3.0f64..7.0,
        seed in 0u64..1000,
    ) {
        let problem = random_problem(sizes, w, d);
        let out = solve::solve_room(&problem, &SolveOptions { seed, node_budget: 60, ..SolveOptions::default() });
        prop_assert!(!out.has_errors());
        let room = solve::RoomShape::new(&problem.outline).expect("valid");
        let fl = &out.value.floor;
        for (i, a) in fl.iter().enumerate() {
            prop_assert!(room.contains_rect(&a.footprint));
            for b in &fl[i + 1..] {
                prop_assert!(!a.footprint.overlaps(&b.footprint));
            }
        }
        prop_assert_eq!(fl.len() + out.value.unplaced.len(), problem.objects.len());
    }
}

/// The rooms of an example, solved from the checked scene with the sizes written in it.
/// The room problem of the first room of a scene's text (sizes as written), the scene checked.
fn first_room_problem(name: &str, text: &str) -> RoomProblem {
    let mut sources = holoc::source::SourceMap::new();
    let id = sources.add(name, text.to_string());
    let checked = holoc::compile::check_file(&sources, id);
    let Some(scene) = checked.value else { panic!("checks: {:?}", checked.diagnostics) };
    solve::room_problem(&scene, scene.rooms[0].id, &solve::WrittenSizes, Vec::new(), Vec::new())
}

fn example_rooms(name: &str) -> Vec<(RoomProblem, RoomLayout)> {
    let path = format!("{}/examples/{name}.holo", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("example exists");
    let mut sources = holoc::source::SourceMap::new();
    let id = sources.add(&path, text);
    let checked = holoc::compile::check_file(&sources, id);
    let Some(scene) = checked.value else { panic!("{name} checks: {:?}", checked.diagnostics) };
    scene
        .rooms
        .iter()
        .map(|room| {
            let problem =
                solve::room_problem(&scene, room.id, &solve::WrittenSizes, Vec::new(), Vec::new());
            let layout = solve::solve_room(&problem, &SolveOptions::default());
            assert!(!layout.has_errors(), "{name}: {:?}", layout.diagnostics);
            check_hard_rules(&problem, &layout.value);
            (problem, layout.value)
        })
        .collect()
}

#[test]
fn example_scene_rooms_solve_from_the_checked_scene() {
    let mut out = String::new();
    for (problem, layout) in example_rooms("apartment_1b1b") {
        out.push_str(&dump(&problem, &layout));
    }
    insta::with_settings!({snapshot_path => "../snapshots/solve", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!("scene_apartment_1b1b", out);
    });
}

#[test]
fn unusable_rooms_and_objects_are_errors_not_panics() {
    let mut problem = random_problem(vec![(1.0, 1.0, false)], 4.0, 4.0);
    problem.outline = vec![[0.0, 0.0], [0.0, 4.0], [3.0, 5.0], [3.0, 0.0]];
    let out = solve::solve_room(&problem, &SolveOptions::default());
    assert!(out.diagnostics.iter().any(|d| d.code == Code::E0501));
    let mut problem = random_problem(vec![(1.0, 1.0, false)], 4.0, 4.0);
    problem.outline = vec![[0.0, 0.0], [0.0, 1e9], [1e9, 1e9], [1e9, 0.0]];
    assert!(solve::solve_room(&problem, &SolveOptions::default()).has_errors());
    let mut problem = random_problem(vec![(f64::NAN, 1.0, false), (1.0, 1.0, true)], 4.0, 4.0);
    problem.objects[1].constraints[0].target = 5;
    let out = solve::solve_room(&problem, &SolveOptions::default());
    assert_eq!(out.diagnostics.iter().filter(|d| d.code == Code::E0502).count(), 2);
}

/// The DFS keeps the floor connected for a 0.25 m agent (no closed pocket over 0.1 m²) and the
/// use-clearances of every object in every corpus room; the crowded bedroom of 14 objects that
/// all want a wall is fully placed (its `edge` is soft).
#[test]
fn corpus_floors_stay_connected_and_clearances_free() {
    for (name, problem) in solve_corpus::load_all() {
        let opts = SolveOptions::default();
        let out = solve::solve_room(&problem, &opts).value;
        let pocket = solve::largest_pocket_m2(&problem, &out, opts.agent_radius_m);
        assert!(
            pocket <= solve::constraints::MAX_POCKET_M2 + 1e-9,
            "{name}: pocket of {pocket} m²"
        );
        let (kept, total) = solve::use_clearances_kept(&problem, &out);
        assert_eq!(kept, total, "{name}: use-clearances");
        if name == "crowded_bedroom_14" {
            assert_eq!(out.floor.len(), problem.objects.len(), "{name}: {:?}", out.unplaced);
        }
    }
}

/// The meanings of the book's table: `near` is not touching, a coffee table stands 0.3–0.6 m
/// before its sofa, a chair in front of a desk is within reach and faces it, a TV is across
/// the room.
#[test]
fn relations_mean_their_documented_ranges() {
    use solve::{Meaning, Pose, Role, Rot};
    let near = Meaning::of(RelationKind::Near, Role::Other, Role::Other, false);
    assert!(near.min_gap > 0.0 && near.max_gap <= 1.5);
    let nightstand = Meaning::of(RelationKind::Near, Role::SideTable, Role::Bed, true);
    assert_eq!(nightstand.min_gap, 0.0);
    assert_eq!(Role::of("coffee table"), Role::LowTable);
    assert_eq!(Role::of("office chair"), Role::Seat);
    assert_eq!(Role::of("tv stand"), Role::Screen);
    assert_eq!(Role::of("nightstand"), Role::SideTable);
    let coffee = Meaning::of(RelationKind::InFrontOf, Role::LowTable, Role::Sofa, false);
    assert_eq!((coffee.min_gap, coffee.max_gap), (0.3, 0.6));
    let chair = Meaning::of(RelationKind::InFrontOf, Role::Seat, Role::Table, false);
    assert!(chair.face && chair.max_gap <= 0.6);
    let tv = Meaning::of(RelationKind::InFrontOf, Role::Screen, Role::Sofa, false);
    assert!(tv.min_gap >= 1.0);
    // A sofa against z = 0 facing +z, a coffee table touching it: in front, but not usable.
    let sofa = Pose { x: 2.0, z: 0.45, rot: Rot::R0 };
    let touching = Pose { x: 2.0, z: 1.15, rot: Rot::R0 };
    let usable = Pose { x: 2.0, z: 1.6, rot: Rot::R0 };
    let m = |p: &Pose| {
        solve::constraints::relation_meant(
            RelationKind::InFrontOf,
            &coffee,
            p,
            [1.0, 0.5],
            &sofa,
            [2.0, 0.9],
        )
    };
    assert!(!m(&touching).satisfied);
    assert!(m(&usable).satisfied, "{:?}", m(&usable));
}

/// Flat things of the same name that do not fit side by side on a receptacle's top are piled,
/// each resting on the one below and no larger than it, the top one no more than
/// `PILE_MAX_M` above the receptacle; things that are not flat, or are of another name, are
/// left out (W0501) instead.
#[test]
fn flat_things_that_do_not_fit_side_by_side_are_piled() {
    let shelf = FloorObject {
        id: "shelf-0".into(),
        size: [0.6, 0.35],
        height: 1.0,
        global: GlobalKind::Edge,
        role: holoc::solve::Role::Other,
        constraints: Vec::new(),
        pin: None,
        thor_type: None,
        span: None,
    };
    let small = |item: &str, k: usize, size: [f64; 3]| SmallObject {
        id: format!("{item}-{k}|shelf-0"),
        item: item.to_string(),
        size,
        on: holoc::solve::Holder::Floor(0),
        elsewhere: None,
        absent: None,
        anchor: Vec::new(),
        thor_type: None,
        span: None,
    };
    let mut small_objects: Vec<SmallObject> =
        (0..10).map(|k| small("book", k, [0.2, 0.28, 0.03])).collect();
    small_objects.push(small("vase", 0, [0.2, 0.2, 0.3]));
    small_objects.push(small("plate", 0, [0.15, 0.15, 0.02]));
    let problem = RoomProblem {
        name: "study".into(),
        outline: vec![[0.0, 0.0], [0.0, 3.0], [3.0, 3.0], [3.0, 0.0]],
        wall_height: 2.7,
        keep_out: vec![vec![[1.0, 0.0], [1.0, 1.0], [2.0, 1.0], [2.0, 0.0]]],
        walls: Vec::new(),
        objects: vec![shelf],
        wall_objects: Vec::new(),
        small_objects,
        ceiling: None,
        span: None,
    };
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    let top = 1.0;
    let placed: Vec<&holoc::solve::PlacedObject> = out.small.iter().collect();
    let books: Vec<_> = placed.iter().filter(|p| p.id.starts_with("book")).collect();
    let on_top = books.iter().filter(|p| (p.position_m[1] - (top + 0.015)).abs() < 1e-9).count();
    assert_eq!(on_top, 2, "two books side by side on a 0.56 m top: {placed:#?}");
    // Each pile: books of 3 cm, the top one resting at most 10 cm above the shelf's top.
    let most_per_pile =
        1 + (1..10).take_while(|&k| f64::from(k) * 0.03 <= holoc::solve::PILE_MAX_M + 1e-9).count();
    assert_eq!(books.len(), 2 * most_per_pile, "{placed:#?}");
    for b in &books {
        let bottom = b.position_m[1] - 0.015;
        assert!(bottom <= top + holoc::solve::PILE_MAX_M + 1e-9, "{b:?}");
        if bottom > top + 1e-9 {
            // It rests on a book right under it, centred on it.
            let under = books.iter().find(|u| {
                (u.position_m[1] + 0.015 - bottom).abs() < 1e-9
                    && (u.position_m[0] - b.position_m[0]).abs() < 1e-9
                    && (u.position_m[2] - b.position_m[2]).abs() < 1e-9
            });
            assert!(under.is_some(), "{b:?} rests on nothing: {placed:#?}");
        }
    }
    // The vase is not flat and the plate is no book: both are left out, with the reason, as
    // are the books the two piles cannot take.
    let left: Vec<&str> = out.unplaced.iter().map(|u| u.id.as_str()).collect();
    assert!(left.contains(&"vase-0|shelf-0") && left.contains(&"plate-0|shelf-0"), "{left:?}");
    assert_eq!(left.len(), 2 + 10 - books.len(), "{left:?}");
    assert!(out.unplaced.iter().all(|u| u.reason.contains("is full")), "{:?}", out.unplaced);
}

/// A thing moved off a receptacle that people do not put it on goes to the nearest one that
/// takes it *and has room for it*: with the nearer side table's top full, the lamp goes to the
/// farther one; with both full it is left out, and the reason names both.
#[test]
fn a_moved_thing_goes_to_the_next_receptacle_when_the_nearest_is_full() {
    let floor = |id: &str, size: [f64; 2], height: f64, thor: &str, pin: [f64; 2]| FloorObject {
        id: id.into(),
        size,
        height,
        global: GlobalKind::Edge,
        role: holoc::solve::Role::Other,
        constraints: Vec::new(),
        pin: Some(holoc::solve::Pose { x: pin[0], z: pin[1], rot: holoc::solve::Rot::R0 }),
        thor_type: Some(thor.into()),
        span: None,
    };
    let small = |id: &str, item: &str, on: usize, size: [f64; 3], elsewhere: Option<Vec<usize>>| {
        SmallObject {
            id: id.into(),
            item: item.into(),
            size,
            on: holoc::solve::Holder::Floor(on),
            elsewhere: elsewhere.map(|v| v.into_iter().map(holoc::solve::Holder::Floor).collect()),
            absent: None,
            anchor: Vec::new(),
            thor_type: None,
            span: None,
        }
    };
    let problem = |fill_far: bool| {
        let mut small_objects = vec![
            // A plant that fills the near table's 0.4 m top.
            small("plant-0|near-0", "plant", 1, [0.36, 0.36, 0.4], None),
            small("lamp-0|chair-0", "lamp", 0, [0.3, 0.3, 0.5], Some(vec![1, 2])),
        ];
        if fill_far {
            small_objects.insert(1, small("vase-0|far-0", "vase", 2, [0.36, 0.36, 0.3], None));
        }
        RoomProblem {
            name: "den".into(),
            outline: vec![[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]],
            wall_height: 2.7,
            keep_out: Vec::new(),
            walls: Vec::new(),
            objects: vec![
                floor("chair-0", [0.8, 0.8], 0.9, "ArmChair", [1.0, 0.5]),
                floor("near-0", [0.4, 0.4], 0.6, "SideTable", [1.8, 0.3]),
                floor("far-0", [0.4, 0.4], 0.6, "SideTable", [3.5, 0.3]),
            ],
            wall_objects: Vec::new(),
            small_objects,
            ceiling: None,
            span: None,
        }
    };
    let out = solve::solve_room(&problem(false), &SolveOptions::default()).value;
    let lamp = out.small.iter().find(|p| p.id == "lamp-0|chair-0");
    let lamp = lamp.unwrap_or_else(|| panic!("the lamp is left out: {:?}", out.unplaced));
    assert_eq!(lamp.on, Some(holoc::solve::Holder::Floor(2)), "{lamp:?}");
    assert!((lamp.position_m[0] - 3.5).abs() < 0.2, "{lamp:?}");
    assert!(out.small.iter().any(|p| p.id == "plant-0|near-0"), "the plant keeps its table");
    assert_eq!(out.moved.len(), 1, "{:?}", out.moved);
    assert_eq!(out.moved[0].to, holoc::solve::Holder::Floor(2));
    assert_eq!(out.moved[0].full, vec![holoc::solve::Holder::Floor(1)]);

    let out = solve::solve_room(&problem(true), &SolveOptions::default()).value;
    assert!(out.small.iter().all(|p| p.id != "lamp-0|chair-0"), "{:?}", out.small);
    assert!(out.moved.is_empty(), "{:?}", out.moved);
    let left = out.unplaced.iter().find(|u| u.id == "lamp-0|chair-0");
    let left = left.unwrap_or_else(|| panic!("the lamp is not reported: {:?}", out.unplaced));
    assert!(left.reason.contains("`near-0`") && left.reason.contains("`far-0`"), "{}", left.reason);
    // The things declared on the tables keep them.
    assert!(out.small.iter().any(|p| p.id == "plant-0|near-0"));
    assert!(out.small.iter().any(|p| p.id == "vase-0|far-0"));
}

/// A pinned pose is held to every hard rule the search keeps, reachability included: a
/// cabinet pinned across a corridor, 45 cm from either wall, cuts off the room behind it for a
/// 0.25 m agent and is reported (W0502), by both
/// solvers.
#[test]
fn a_pin_that_cuts_the_room_off_is_reported() {
    let object = |id: &str, size: [f64; 2], pin: Option<solve::Pose>| FloorObject {
        id: id.into(),
        size,
        height: 1.0,
        global: if pin.is_some() { GlobalKind::Middle } else { GlobalKind::Edge },
        role: holoc::solve::Role::Other,
        constraints: Vec::new(),
        pin,
        thor_type: None,
        span: None,
    };
    let problem = RoomProblem {
        name: "corridor".into(),
        outline: vec![[0.0, 0.0], [0.0, 4.0], [3.0, 4.0], [3.0, 0.0]],
        wall_height: 2.7,
        keep_out: vec![vec![[1.0, 0.0], [1.0, 1.0], [2.0, 1.0], [2.0, 0.0]]],
        walls: Vec::new(),
        objects: vec![
            object("shelf-0", [0.8, 0.4], None),
            object(
                "cabinet-0",
                [2.1, 0.5],
                Some(solve::Pose { x: 1.5, z: 2.0, rot: solve::Rot::from_deg(0.0) }),
            ),
        ],
        wall_objects: Vec::new(),
        small_objects: Vec::new(),
        ceiling: None,
        span: None,
    };
    for solver in [solve::Solver::Dfs, solve::Solver::Milp] {
        let out = solve::solve_room(&problem, &SolveOptions { solver, ..SolveOptions::default() });
        assert!(
            out.value.pinned_breaks.iter().any(|&(k, r)| k == 1 && r == solve::HardRule::Reachable),
            "{solver:?}: {:?}",
            out.value.pinned_breaks
        );
        assert!(out.diagnostics.iter().any(|d| d.code.as_str() == "W0502"));
    }
}

/// A shelf whose plant stands `near` it, and one piece of wall left between a pinned cabinet and
/// the doors' zones: 1.125 m, for 0.62 m of shelf, the 0.10 m a plant stands off its shelf and
/// 0.40 m of plant. The wall poses of the grid step 10 cm along the wall and miss the 5 mm the
/// two have to spare; the shelf also looks at the wall poses flush beside what stands there
/// (the cabinet), so both stand against the wall and the plant near its shelf.
#[test]
fn a_shelf_and_its_plant_share_a_piece_of_wall_only_just_wide_enough() {
    let object = |id: &str, size: [f64; 2], constraints: Vec<ProblemConstraint>| FloorObject {
        id: id.into(),
        size,
        height: 1.0,
        global: GlobalKind::Edge,
        role: holoc::solve::Role::Other,
        constraints,
        pin: None,
        thor_type: None,
        span: None,
    };
    let near = ProblemConstraint {
        kind: RelationKind::Near,
        written: RelationKind::Near,
        implied: false,
        target: 1,
        span: None,
    };
    let zone = |a: [f64; 2], b: [f64; 2]| vec![a, [a[0], b[1]], b, [b[0], a[1]]];
    let mut cabinet = object("cabinet-0", [0.985, 0.4], Vec::new());
    cabinet.pin = Some(solve::Pose { x: 0.4925, z: 0.2, rot: solve::Rot::from_deg(0.0) });
    let problem = RoomProblem {
        name: "one_piece_of_wall".into(),
        outline: vec![[0.0, 0.0], [0.0, 3.0], [3.0, 3.0], [3.0, 0.0]],
        wall_height: 2.7,
        // Beyond the cabinet, every wall but 1.125 m of the bottom one (x from 0.985 to 2.11)
        // lies in a door's zone.
        keep_out: vec![
            zone([2.11, 0.0], [3.0, 0.6]),
            zone([0.0, 0.6], [0.6, 3.0]),
            zone([2.4, 0.6], [3.0, 3.0]),
            zone([0.6, 2.4], [2.4, 3.0]),
        ],
        walls: Vec::new(),
        objects: vec![
            cabinet,
            object("shelf-0", [0.62, 0.4], Vec::new()),
            object("plant-0", [0.4, 0.4], vec![near]),
        ],
        wall_objects: Vec::new(),
        small_objects: Vec::new(),
        ceiling: None,
        span: None,
    };
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    assert_eq!(out.floor.len(), 3, "{:?}", out.unplaced);
    for p in &out.floor {
        for c in &p.constraints {
            assert!(
                c.measure.satisfied,
                "{}: {} {:?}",
                problem.objects[p.index].id, c.text, c.measure
            );
        }
        assert!(
            p.footprint.min_z.abs() < 1e-9,
            "{} against the bottom wall",
            problem.objects[p.index].id
        );
    }
}

/// The rank of a layout in the documented order: objects placed, then constraints kept.
fn rank(problem: &RoomProblem, layout: &RoomLayout) -> (usize, usize) {
    (layout.floor.len(), layout.constraint_tally(problem).0)
}

/// More search never loses what less search found: the search walks the same nodes first and
/// keeps the best complete layout under the documented order.
#[test]
fn a_larger_budget_never_gives_a_worse_layout() {
    for name in [
        "restaurant_34",
        "restaurant_tables_first",
        "restaurant_chain",
        "packed_bedroom_60",
        "kitchen",
    ] {
        let problem = solve_corpus::load(&solve_corpus::corpus_dir().join(format!("{name}.json")));
        let mut last = (0, 0);
        for budget in [20, 100, 400, 1000, 2500] {
            let opts = SolveOptions { node_budget: budget, ..SolveOptions::default() };
            let r = rank(&problem, &solve::solve_room(&problem, &opts).value);
            assert!(r >= last, "{name}: budget {budget} gives {r:?}, less gave {last:?}");
            last = r;
        }
    }
}

/// Rooms whose first layout breaks a relation that no pose can keep walked their whole search
/// proving it (the arcade 751 nodes, the kitchen 465, the reading room its 1,000). A round of
/// discrepancy now tries other poses only for the objects round what the best layout so far
/// loses (the object, its targets, what relates to it and what stands within reach of them):
/// the same relations kept in far fewer nodes.
#[test]
fn a_search_spends_its_discrepancies_round_what_the_layout_loses() {
    for (name, kept, most_nodes) in
        [("arcade", 32, 120), ("kitchen", 16, 150), ("reading_room", 30, 600)]
    {
        let problem = solve_corpus::load(&solve_corpus::corpus_dir().join(format!("{name}.json")));
        let out = solve::solve_room(&problem, &SolveOptions::default()).value;
        let (ok, _) = out.constraint_tally(&problem);
        assert_eq!((out.floor.len(), ok), (problem.objects.len(), kept), "{name}");
        assert!(out.nodes <= most_nodes, "{name}: {} nodes", out.nodes);
    }
}

/// How many chairs `around` a table keep the relation, and how many there are.
fn chairs_at_tables(problem: &RoomProblem, layout: &RoomLayout) -> (usize, usize) {
    let mut kept = 0;
    for p in &layout.floor {
        kept += p
            .constraints
            .iter()
            .filter(|c| c.kind == Some(RelationKind::Around) && c.measure.satisfied)
            .count();
    }
    let total = problem
        .objects
        .iter()
        .flat_map(|o| &o.constraints)
        .filter(|c| c.kind == RelationKind::Around)
        .count();
    (kept, total)
}

/// A restaurant written tables first, then every chair: the tables keep room for their chairs
/// instead of being pulled together, and the chairs sit at their own table.
#[test]
fn crowded_rooms_keep_their_groups() {
    for (name, at_least) in
        [("restaurant_tables_first", 23), ("restaurant_34", 23), ("restaurant_chain", 24)]
    {
        let problem = solve_corpus::load(&solve_corpus::corpus_dir().join(format!("{name}.json")));
        let out = solve::solve_room(&problem, &SolveOptions::default()).value;
        let (kept, total) = chairs_at_tables(&problem, &out);
        assert_eq!(total, 24, "{name}");
        assert!(kept >= at_least, "{name}: {kept} of {total} chairs at their table");
    }
    // Rows of desks, each chair in front of its desk and facing it.
    let problem = solve_corpus::load(&solve_corpus::corpus_dir().join("classroom_rows.json"));
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    assert_eq!(out.floor.len(), problem.objects.len());
    for p in out.floor.iter().filter(|p| problem.objects[p.index].id.starts_with("chair-")) {
        for c in &p.constraints {
            assert!(c.measure.satisfied, "{}: {} not kept", problem.objects[p.index].id, c.text);
        }
    }
    // Generated rooms of 40 and 80 objects: everything placed.
    for name in ["generated_40", "generated_80", "packed_bedroom_60"] {
        let problem = solve_corpus::load(&solve_corpus::corpus_dir().join(format!("{name}.json")));
        let out = solve::solve_room(&problem, &SolveOptions::default()).value;
        assert_eq!(out.floor.len(), problem.objects.len(), "{name}: {:?}", out.unplaced);
    }
}

/// Eighty objects in 176 m², 47 of them against the walls (about 40 m of the 49 m of wall the
/// doors leave), written as a generator lists them, a sofa after shelves and plants: placed
/// group by group, the groups with the most floor first, every object stands and every one that
/// wants a wall has one (in plan order the last sofa found no 2 m of wall left and stood in the
/// middle of the room: 150 of 156); every plant stands near its shelf (with wall poses 25 cm
/// apart, two plants found no wall beside their shelves: 154 of 156); and the layout comes back
/// in plan order.
#[test]
fn a_room_of_eighty_puts_every_wall_piece_on_a_wall() {
    let problem = solve_corpus::load(&solve_corpus::corpus_dir().join("generated_80.json"));
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    assert_eq!(out.floor.len(), 80, "{:?}", out.unplaced);
    for p in &out.floor {
        let global = &p.constraints[0];
        assert!(
            global.measure.satisfied,
            "{}: {} not kept",
            problem.objects[p.index].id, global.text
        );
    }
    let (kept, total) = out.constraint_tally(&problem);
    assert_eq!(kept, total, "every relation kept");
    assert!(out.floor.windows(2).all(|w| w[0].index < w[1].index), "plan order");
    // Found by the greedy pass: a shelf no longer goes where the only piece of wall left for
    // its plant lies in the legroom of the sofa beside it (the search then walked 318 nodes).
    // Since issue 48 (seats keep their 0.45 m front strip, storage its doors' swing) the
    // search walks on to its layout (it was 80); since issue 49 it spends its discrepancies
    // only on the objects round what the best layout so far loses: 249 nodes (331 before).
    // Since a shelf with a plant to come also looks at the wall poses flush beside what is
    // placed (the gaps the grid's 15 cm steps along the walls miss), the greedy pass keeps
    // every relation: 80 nodes.
    assert_eq!(out.nodes, 80, "found at node {} of {}", out.found_at, out.nodes);
}

/// An L-shaped living room whose TV stand wants a wall `in front of` the sofa and faces it:
/// the sofa stands where a wall lies across from it within the relation's range, and the TV
/// stand there faces it (with the sofa against the far wall of the arm, the stand found no wall
/// in front of it and stood on a side wall, 81° away from facing it).
#[test]
fn a_tv_stand_that_wants_a_wall_faces_the_sofa_across_the_room() {
    let problem = solve_corpus::load(&solve_corpus::corpus_dir().join("l_shaped_living.json"));
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    let tv = problem.objects.iter().position(|o| o.id == "tv_stand-0").expect("a tv stand");
    let placed = out.floor.iter().find(|p| p.index == tv).expect("the tv stand stands");
    for c in &placed.constraints {
        assert!(c.measure.satisfied, "tv_stand-0: {} not kept: {:?}", c.text, c.measure);
    }
}

/// The objects left out come back in plan order, whatever order the search placed them in.
#[test]
fn objects_left_out_are_listed_in_plan_order() {
    let mut problem = solve_corpus::load(&solve_corpus::corpus_dir().join("infeasible.json"));
    // A free-standing stage too large for the room, written last: the search tries it first.
    let mut stage = problem.objects[0].clone();
    stage.id = "stage-9".into();
    stage.size = [3.0, 3.0];
    stage.global = GlobalKind::Middle;
    stage.constraints.clear();
    problem.objects.push(stage);
    let out = solve::solve_room(&problem, &SolveOptions::default());
    let index = |id: &str| problem.objects.iter().position(|o| o.id == id);
    let left: Vec<_> = out.value.unplaced.iter().map(|u| index(&u.id)).collect();
    assert_eq!(left, vec![Some(0), Some(2), Some(4)]);
    assert!(out.value.floor.windows(2).all(|w| w[0].index < w[1].index));
    let reported: Vec<_> = out.diagnostics.iter().filter(|d| d.code == Code::W0501).collect();
    assert_eq!(reported.len(), 3);
}

/// The classroom example: rows of desks facing the teacher's desk, each chair at the middle of
/// its own desk (not where two desks of a row meet), an aisle behind every row's chairs, and
/// the teacher's desk keeping its pull-out space (no student desk against it).
#[test]
fn the_classroom_has_rows_of_desks_with_their_chairs() {
    let rooms = example_rooms("classroom");
    let (problem, layout) = &rooms[0];
    assert_eq!(layout.floor.len(), problem.objects.len(), "{:?}", layout.unplaced);
    let (kept, total) = layout.constraint_tally(problem);
    assert_eq!(kept, total, "every relation kept");
    let placed = |id: &str| {
        let p = layout.floor.iter().find(|p| problem.objects[p.index].id == id);
        p.unwrap_or_else(|| panic!("{id} placed"))
    };
    let teacher = placed("teacher_desk-0");
    let pull_out = solve::constraints::front_zone(
        &teacher.pose,
        problem.objects[teacher.index].size,
        solve::constraints::DESK_CLEARANCE_M,
    );
    for i in 0..12 {
        let desk = placed(&format!("student_desk-{i}"));
        let chair = placed(&format!("student_chair-{i}"));
        assert!(!desk.footprint.overlaps(&pull_out), "student_desk-{i} in the teacher's space");
        // Along the desk's edge the chair's centre is at the desk's centre (the desks of a
        // row are 0.7 m wide: a chair where two meet would be 0.35 m off).
        let right = desk.pose.rot.right();
        let off = (chair.pose.x - desk.pose.x) * right[0] + (chair.pose.z - desk.pose.z) * right[1];
        assert!(off.abs() <= 0.1, "student_chair-{i} is {off:.2} m off its desk's middle");
    }
    // Rows 4–7 behind 0–3 and 8–11 behind 4–7: the chair between them and an aisle.
    for (front, back) in [(0, 4), (4, 8)] {
        let a = placed(&format!("student_desk-{front}"));
        let b = placed(&format!("student_desk-{back}"));
        let chair_depth = problem.objects[placed(&format!("student_chair-{front}")).index].size[1];
        let gap = a.footprint.gap(&b.footprint);
        assert!(
            gap >= chair_depth + 2.0 * solve::constraints::AGENT_RADIUS_M - 1e-6,
            "student_desk-{back} is {gap:.2} m behind student_desk-{front}: no aisle"
        );
    }
}

/// A desk keeps 0.75 m before it for its chair: the chair drawn up to it stands there, another
/// desk `in front of` it stands beyond; a chair between two desks of a row goes to the middle
/// of its own.
#[test]
fn a_desk_keeps_its_pull_out_space_for_its_chair_alone() {
    let obj = |id: &str, size: [f64; 2], role, global, constraints| FloorObject {
        id: id.into(),
        size,
        height: 0.75,
        global,
        role,
        constraints,
        pin: None,
        thor_type: None,
        span: None,
    };
    let rel = |kind, target| ProblemConstraint {
        kind,
        written: kind,
        implied: false,
        target,
        span: None,
    };
    let problem = RoomProblem {
        name: "study".into(),
        outline: vec![[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]],
        wall_height: 2.7,
        keep_out: vec![vec![[0.0, 0.0], [0.0, 0.9], [0.9, 0.9], [0.9, 0.0]]],
        walls: Vec::new(),
        objects: vec![
            obj("desk-0", [1.2, 0.6], Role::Desk, GlobalKind::Edge, Vec::new()),
            obj(
                "table-0",
                [0.8, 0.6],
                Role::Desk,
                GlobalKind::Middle,
                vec![rel(RelationKind::InFrontOf, 0)],
            ),
            obj(
                "chair-0",
                [0.45, 0.45],
                Role::Seat,
                GlobalKind::Middle,
                vec![rel(RelationKind::InFrontOf, 0), rel(RelationKind::FaceTo, 0)],
            ),
        ],
        wall_objects: Vec::new(),
        small_objects: Vec::new(),
        ceiling: None,
        span: None,
    };
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    check_hard_rules(&problem, &out);
    assert_eq!(out.floor.len(), 3, "{:?}", out.unplaced);
    let at = |id: &str| out.floor.iter().find(|p| problem.objects[p.index].id == id).expect(id);
    let desk = at("desk-0");
    let zone = solve::constraints::front_zone(
        &desk.pose,
        [1.2, 0.6],
        solve::constraints::DESK_CLEARANCE_M,
    );
    assert!(at("chair-0").footprint.overlaps(&zone), "the chair is drawn up to its desk");
    assert!(!at("table-0").footprint.overlaps(&zone), "the other desk keeps out of the way");
    let (kept, total) = out.constraint_tally(&problem);
    assert_eq!(kept, total);
}

/// Three small rooms in a row, each with an object that cannot be placed (W0501).
const THREE_ROOMS: &str = include_str!("lsp/three_rooms.holo");

/// A room as the callback of `solve_by_room` got it: its index, its relations given up and
/// its own diagnostics.
type RoomSaid = (usize, Vec<holoc::diag::Diagnostic>, Vec<holoc::diag::Diagnostic>);

/// Builds `text` whole (`holoc build`) and room by room with each room first in turn: every
/// order gives the same layout, byte for byte, and the same diagnostics, and the rooms handed
/// to the callback, gathered in room order, are the whole solve's diagnostics.
fn by_room_matches_the_whole_solve(name: &str, text: &str) {
    use std::sync::Mutex;
    let mut sources = holoc::source::SourceMap::new();
    let file = sources.add(name, text);
    let catalog = holoc::resolve::Catalog::embedded();
    let options = holoc::compile::BuildOptions::new(&catalog);
    let whole = holoc::compile::build(&sources, file, &options);
    let built = whole.value.as_ref().expect("the scene builds");
    let whole_dump = built.layout.dump(&built.scene);
    let room_names: Vec<String> = built.scene.rooms.iter().map(|r| r.name.clone()).collect();
    assert!(room_names.len() >= 2, "{name}: a scene of several rooms");
    let firsts = std::iter::once(None).chain(room_names.iter().map(|n| Some(n.as_str())));
    for first in firsts {
        let seen: Mutex<Vec<RoomSaid>> = Mutex::new(Vec::new());
        let on_room = |_: &holoc::check::Scene, done: solve::RoomDone<'_>| {
            let mut seen = seen.lock().expect("not poisoned");
            seen.push((done.index, done.given_up.to_vec(), done.diagnostics.to_vec()));
        };
        let by_room = holoc::compile::solve_by_room(&sources, file, &options, first, &on_room);
        let layout = by_room.value.as_ref().expect("solved");
        assert_eq!(layout.dump(&built.scene), whole_dump, "{name}, {first:?} first");
        // Every stage's diagnostics up to the solver, as `build` gives them (lower adds none).
        assert_eq!(by_room.diagnostics, whole.diagnostics, "{name}, {first:?} first");
        let mut seen = seen.into_inner().expect("not poisoned");
        assert_eq!(seen.len(), room_names.len(), "{name}: every room reported once");
        if let Some(first) = first {
            assert_eq!(room_names[seen[0].0], first, "{name}: the room asked for comes first");
        }
        seen.sort_by_key(|(index, ..)| *index);
        let gathered: Vec<holoc::diag::Diagnostic> = (seen.iter().flat_map(|(_, g, _)| g.clone()))
            .chain(seen.iter().flat_map(|(_, _, d)| d.clone()))
            .collect();
        let solver: Vec<holoc::diag::Diagnostic> =
            whole.diagnostics.iter().filter(|d| d.code.stage() == "solve").cloned().collect();
        assert_eq!(gathered, solver, "{name}, {first:?} first");
    }
}

#[test]
fn rooms_solved_one_by_one_give_the_whole_solves_layout_in_any_order() {
    by_room_matches_the_whole_solve("three_rooms.holo", THREE_ROOMS);
    let apartment = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/apartment_1b1b.holo"
    ))
    .expect("example exists");
    by_room_matches_the_whole_solve("apartment_1b1b.holo", &apartment);
}

#[test]
fn a_cancelled_solve_reports_no_room_after_the_cancellation() {
    let mut sources = holoc::source::SourceMap::new();
    let file = sources.add("three_rooms.holo", THREE_ROOMS);
    let catalog = holoc::resolve::Catalog::embedded();
    let options = holoc::compile::BuildOptions::new(&catalog);
    let token = holoc::cancel::Token::new("solve");
    let _scope = holoc::cancel::scoped(Some(std::sync::Arc::clone(&token)));
    // The first room reported cancels the work: no other room is reported, and no layout.
    let reported = std::sync::atomic::AtomicUsize::new(0);
    let on_room = |_: &holoc::check::Scene, done: solve::RoomDone<'_>| {
        assert_eq!(done.index, 1, "the room asked for first");
        reported.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        token.cancel();
    };
    let out = holoc::compile::solve_by_room(&sources, file, &options, Some("middle"), &on_room);
    assert!(out.value.is_none());
    assert_eq!(reported.load(std::sync::atomic::Ordering::SeqCst), 1);
}

/// A pass of discrepancy tries the anchor's other poses before the later objects': a
/// restaurant whose tables come first finds every chair its seat once its first table stands
/// elsewhere, long before a pass from the bottom up would move that table.
#[test]
fn a_pass_tries_the_anchors_other_poses_first() {
    let problem =
        solve_corpus::load(&solve_corpus::corpus_dir().join("restaurant_tables_first.json"));
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    let (kept, total) = out.constraint_tally(&problem);
    assert_eq!(kept, total, "{kept} of {total}");
    assert!(out.found_at <= 100, "found at node {} (497 from the bottom up)", out.found_at);
}

/// A student desk faces the teacher and its chair is drawn up `behind` it: the desk is used
/// from behind, so its pull-out space is there, where its chair stands, and not in front, where
/// it would keep the row ahead (and that row's chairs) 0.75 m further off. In the corpus's
/// classroom every student chair stands in its own desk's pull-out space, and a desk whose
/// chair is drawn up in front of it (the teacher's desk of `classroom_rows`) keeps its space
/// in front.
#[test]
fn a_desk_used_from_behind_keeps_its_pull_out_space_behind() {
    let problem = solve_corpus::load(&solve_corpus::corpus_dir().join("classroom_25.json"));
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    let pose_of = |k: usize| out.floor.iter().find(|p| p.index == k);
    let mut chairs = 0;
    for (j, o) in problem.objects.iter().enumerate() {
        let Some(c) = o.constraints.iter().find(|c| c.kind == RelationKind::Behind) else {
            continue;
        };
        if !o.id.starts_with("student_chair") {
            continue;
        }
        let (Some(chair), Some(desk)) = (pose_of(j), pose_of(c.target)) else { continue };
        let (zones, _) = solve::use_zones_of(&problem, c.target, &desk.pose);
        assert!(
            zones.iter().any(|z| z.overlaps(&chair.footprint)),
            "{} does not stand in the pull-out space of {}",
            o.id,
            problem.objects[c.target].id
        );
        chairs += 1;
    }
    assert!(chairs >= 10, "{chairs} student chairs checked");
    let rows = solve_corpus::load(&solve_corpus::corpus_dir().join("classroom_rows.json"));
    let out = solve::solve_room(&rows, &SolveOptions::default()).value;
    let (teacher, chair) = (0, 1);
    let desk = out.floor.iter().find(|p| p.index == teacher).expect("the teacher's desk stands");
    let seat = out.floor.iter().find(|p| p.index == chair).expect("the teacher's chair stands");
    let (zones, _) = solve::use_zones_of(&rows, teacher, &desk.pose);
    assert!(zones.iter().any(|z| z.overlaps(&seat.footprint)), "the teacher sits at the desk");
}

/// A classroom planned as the original system's plans write it: ten student desks facing the
/// teacher's desk, each chair only `near` its desk. A chair `near` a desk is drawn up to it
/// (issue 48): every chair stands within 0.6 m of its own desk, facing the way its desk faces
/// (at its back, towards the teacher), and every desk faces the teacher's desk.
#[test]
fn a_chair_near_its_desk_is_drawn_up_to_it() {
    let mut text = String::from(
        "scene \"a classroom\" {\n  wall height 3 m\n  seed 3\n}\n\nroom classroom \"classroom\" {\n  corners in m (0, 0) (0, 8) (7, 8) (7, 0)\n\n  object teacher_desk \"teacher desk\" {\n    size 140 cm x 70 cm x 76 cm\n    edge\n  }\n  object student_desk \"student desk\" {\n    size 70 cm x 50 cm x 72 cm\n    count 10 same\n    middle\n    face to teacher_desk-0\n  }\n  object student_chair \"student chair\" {\n    size 45 cm x 45 cm x 80 cm\n    count 10 same\n    middle\n",
    );
    for i in 0..10 {
        let _ = write!(
            text,
            "    instance student_chair-{i} {{\n      near student_desk-{i}\n    }}\n"
        );
    }
    text.push_str("  }\n}\n\ndoor exterior -- classroom : doorway single \"door\"\n");
    let problem = first_room_problem("classroom_near.holo", &text);
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    check_hard_rules(&problem, &out);
    assert_eq!(out.floor.len(), problem.objects.len(), "{:?}", out.unplaced);
    let placed = |id: &str| {
        let p = out.floor.iter().find(|p| problem.objects[p.index].id == id);
        p.unwrap_or_else(|| panic!("{id} placed"))
    };
    let teacher = placed("teacher_desk-0");
    let mut facing = 0;
    for i in 0..10 {
        let desk = placed(&format!("student_desk-{i}"));
        let chair = placed(&format!("student_chair-{i}"));
        // Turned towards the teacher's desk (rows wider than it: within 45° of its centre).
        let angle = solve::constraints::angle_to(&desk.pose, teacher.footprint.center());
        facing += usize::from(angle <= 45.0);
        let gap = chair.footprint.gap(&desk.footprint);
        assert!(gap <= 0.6 + 1e-6, "student_chair-{i} is {gap:.2} m from its desk");
        assert!(
            solve::constraints::faces(&chair.pose, &desk.footprint),
            "student_chair-{i} does not face its desk"
        );
        assert_eq!(chair.pose.rot, desk.pose.rot, "student_chair-{i} sits the way its desk faces");
        for c in &chair.constraints {
            assert!(c.measure.satisfied, "student_chair-{i}: {} not kept", c.text);
        }
    }
    // Every desk turned to the teacher's desk (issue 48): a set of desks that all `face to`
    // it stands in rows facing it (`solve::desk_rows`).
    assert_eq!(facing, 10, "{facing} of 10 desks turned towards the teacher's desk");
    for i in 0..10 {
        let desk = placed(&format!("student_desk-{i}"));
        let face = desk.constraints.iter().find(|c| c.text == "face to teacher_desk-0");
        assert!(face.is_some_and(|c| c.measure.satisfied), "student_desk-{i} faces away");
    }
    // The rows are implied relations, printed as such.
    let second = placed("student_desk-1");
    assert!(
        second.constraints.iter().any(|c| c.text == "side of student_desk-0 (rows)"),
        "{:?}",
        second.constraints.iter().map(|c| &c.text).collect::<Vec<_>>()
    );
    // The report prints the relation as written.
    let chair = placed("student_chair-0");
    assert_eq!(chair.constraints[1].text, "near student_desk-0");
}

/// The same classroom with the MILP: every desk turned to the teacher's desk.
#[test]
fn the_milp_turns_every_desk_to_the_teacher() {
    let mut text = String::from(
        "scene \"a classroom\" {\n  wall height 3 m\n  seed 3\n}\n\nroom classroom \"classroom\" {\n  corners in m (0, 0) (0, 8) (7, 8) (7, 0)\n\n  object teacher_desk \"teacher desk\" {\n    size 140 cm x 70 cm x 76 cm\n    edge\n  }\n  object student_desk \"student desk\" {\n    size 70 cm x 50 cm x 72 cm\n    count 10 same\n    middle\n    face to teacher_desk-0\n  }\n}\n\ndoor exterior -- classroom : doorway single \"door\"\n",
    );
    text.push('\n');
    let problem = first_room_problem("classroom_milp.holo", &text);
    let opts = SolveOptions { solver: solve::Solver::Milp, ..SolveOptions::default() };
    let out = solve::solve_room(&problem, &opts).value;
    assert_eq!(out.floor.len(), problem.objects.len(), "{:?}", out.unplaced);
    for p in &out.floor {
        let o = &problem.objects[p.index];
        if !o.id.starts_with("student_desk") {
            continue;
        }
        let face = p.constraints.iter().find(|c| c.text == "face to teacher_desk-0");
        assert!(face.is_some_and(|c| c.measure.satisfied), "{} faces away", o.id);
    }
}

/// What a person stands in front of to cook or wash keeps the place free where they stand
/// (issue 48): a stove, range, oven, dishwasher, washing machine or dryer 0.9 m, a sink or
/// washbasin 0.75 m; the kitchen island `in front of` the stove stands beyond it.
#[test]
fn a_stove_keeps_the_place_where_its_cook_stands() {
    use solve::constraints::{front_zone, APPLIANCE_CLEARANCE_M, BASIN_CLEARANCE_M};
    for (words, role) in [
        ("gas stove", Role::Appliance),
        ("electric range", Role::Appliance),
        ("induction cooktop", Role::Appliance),
        ("wall oven", Role::Appliance),
        ("dishwasher", Role::Appliance),
        ("washing machine", Role::Appliance),
        ("tumble dryer", Role::Appliance),
        ("kitchen sink", Role::Basin),
        ("bathroom vanity", Role::Basin),
        ("sink cabinet", Role::Storage),
        ("range hood", Role::Other),
        ("laundry basket", Role::Other),
    ] {
        assert_eq!(Role::of(words), role, "{words}");
    }
    assert_eq!(Role::Appliance.front_clearance(0.9), APPLIANCE_CLEARANCE_M);
    assert_eq!(Role::Basin.front_clearance(0.9), BASIN_CLEARANCE_M);
    // Nothing stands where the cook stands, related or not.
    assert!(!Role::Appliance.lets_in(Role::Table, true));
    assert!(!Role::Basin.lets_in(Role::Seat, true));
    for solver in [solve::Solver::Dfs, solve::Solver::Milp] {
        let opts = SolveOptions { solver, ..SolveOptions::default() };
        let path = format!("{}/examples/kitchen_island.holo", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("example exists");
        let problem = first_room_problem(&path, &text);
        let out = solve::solve_room(&problem, &opts).value;
        check_hard_rules(&problem, &out);
        let placed = |id: &str| {
            let p = out.floor.iter().find(|p| problem.objects[p.index].id == id);
            p.unwrap_or_else(|| panic!("{id} placed ({solver:?})"))
        };
        let stove = placed("stove-0");
        assert_eq!(problem.objects[stove.index].role, Role::Appliance);
        let strip =
            front_zone(&stove.pose, problem.objects[stove.index].size, APPLIANCE_CLEARANCE_M);
        for p in &out.floor {
            assert!(
                p.index == stove.index || !p.footprint.overlaps(&strip),
                "{} stands where the cook stands ({solver:?})",
                problem.objects[p.index].id
            );
        }
        let island = placed("kitchen_island-0");
        let gap = island.footprint.gap(&stove.footprint);
        assert!(gap >= APPLIANCE_CLEARANCE_M - 1e-6, "the island is {gap:.2} m from the stove");
    }
}

/// A deep living room whose plan relates nothing (the calebchia request: 6 m × 7 m, every
/// piece unplaced, a sofa and a TV stand): the sofa turns to the TV from 1.5–4.5 m, each within
/// 30° of facing the other, the line between them clear, in the DFS and the MILP; the sofa
/// stands off the wall where no two walls are close enough.
#[test]
fn a_sofa_in_a_deep_room_watches_its_tv() {
    let text = "scene \"a living room\" {\n  wall height 2.7 m\n  seed 0\n}\n\nroom living_room \"living room\" {\n  corners in m (0, 0) (0, 7) (6, 7) (6, 0)\n\n  object sectional_sofa \"sectional sofa\" {\n    size 250 cm x 90 cm x 80 cm\n  }\n  object armchair \"armchair\" {\n    size 90 cm x 90 cm x 100 cm\n    count 2 same\n  }\n  object tv_stand \"tv stand\" {\n    size 180 cm x 45 cm x 50 cm\n  }\n  object bookshelf \"bookshelf\" {\n    size 80 cm x 30 cm x 200 cm\n    count 2 same\n  }\n  object coffee_table \"coffee table\" {\n    size 140 cm x 70 cm x 45 cm\n  }\n  object floor_lamp \"floor lamp\" {\n    size 40 cm x 40 cm x 180 cm\n  }\n}\n\ndoor exterior -- living_room : doorway single \"door\"\n";
    let problem = first_room_problem("deep_living.holo", text);
    for solver in [solve::Solver::Dfs, solve::Solver::Milp] {
        let opts = SolveOptions { solver, ..SolveOptions::default() };
        let out = solve::solve_room(&problem, &opts).value;
        check_hard_rules(&problem, &out);
        let placed = |id: &str| {
            let p = out.floor.iter().find(|p| problem.objects[p.index].id == id);
            p.unwrap_or_else(|| panic!("{id} placed ({solver:?})"))
        };
        let (tv, sofa) = (placed("tv_stand-0"), placed("sectional_sofa-0"));
        let gap = tv.footprint.gap(&sofa.footprint);
        assert!((1.5 - 1e-6..=4.5 + 1e-6).contains(&gap), "{solver:?}: the TV is {gap:.2} m away");
        let a = solve::constraints::angle_to(&tv.pose, sofa.footprint.center());
        let b = solve::constraints::angle_to(&sofa.pose, tv.footprint.center());
        assert!(a <= 30.0 + 1e-6 && b <= 30.0 + 1e-6, "{solver:?}: angles {a:.0}° and {b:.0}°");
        let group =
            sofa.constraints.iter().find(|c| c.text == "face to tv_stand-0 (seating group)");
        assert!(group.is_some_and(|c| c.measure.satisfied), "{solver:?}: {:?}", sofa.constraints);
        // Nothing taller than the line of sight stands between them.
        let line = ([tv.pose.x, tv.pose.z], [sofa.pose.x, sofa.pose.z]);
        for p in &out.floor {
            let o = &problem.objects[p.index];
            if p.index == tv.index || p.index == sofa.index || o.height <= 0.6 {
                continue;
            }
            assert!(
                !p.footprint.meets_segment(line.0, line.1),
                "{solver:?}: {} blocks the view",
                o.id
            );
        }
    }
}

/// A living room whose plan relates nothing (every piece `edge`, as the real requests' replay
/// writes it) is still a seating group: the TV stand faces the sofa from 1.5–4.5 m, each
/// within 30° of facing the other.
#[test]
fn a_tv_in_a_room_with_a_sofa_faces_it_at_a_viewing_distance() {
    let text = "scene \"a living room\" {\n  wall height 2.7 m\n  seed 0\n}\n\nroom living_room \"living room\" {\n  corners in m (0, 0) (0, 5) (6.5, 5) (6.5, 0)\n\n  object tv_stand \"tv stand\" {\n    size 180 cm x 45 cm x 55 cm\n    edge\n  }\n  object bookcase \"bookcase\" {\n    size 90 cm x 35 cm x 180 cm\n    edge\n  }\n  object sofa \"sofa\" {\n    size 220 cm x 95 cm x 85 cm\n    edge\n  }\n  object armchair \"armchair\" {\n    size 80 cm x 80 cm x 90 cm\n    edge\n  }\n}\n\ndoor exterior -- living_room : doorway single \"door\"\n";
    let problem = first_room_problem("living.holo", text);
    let out = solve::solve_room(&problem, &SolveOptions::default()).value;
    check_hard_rules(&problem, &out);
    let placed = |id: &str| {
        let p = out.floor.iter().find(|p| problem.objects[p.index].id == id);
        p.unwrap_or_else(|| panic!("{id} placed"))
    };
    let (tv, sofa) = (placed("tv_stand-0"), placed("sofa-0"));
    let gap = tv.footprint.gap(&sofa.footprint);
    assert!((1.5 - 1e-6..=4.5 + 1e-6).contains(&gap), "the TV is {gap:.2} m from the sofa");
    let a = solve::constraints::angle_to(&tv.pose, sofa.footprint.center());
    let b = solve::constraints::angle_to(&sofa.pose, tv.footprint.center());
    assert!(a <= 30.0 + 1e-6 && b <= 30.0 + 1e-6, "angles {a:.0}° and {b:.0}°");
    // Every piece against a wall, the armchair's front strip clear.
    for p in &out.floor {
        assert!(p.constraints[0].measure.satisfied, "{} off the wall", problem.objects[p.index].id);
    }
}

/// The classroom of issue 48 (`tests/rooms/classroom_98.holo`), written as the original
/// system's plans write a classroom: ten desks that `face to` the teacher's desk, each chair
/// `near` and `face to` its desk. It keeps at least 95 of its 98 written relations (each
/// object's global constraint counted), every desk is turned to the teacher's desk, and each
/// chair is drawn up to its own desk, in the DFS; the MILP keeps every desk turned too.
#[test]
fn the_issues_classroom_is_rows_at_their_desks() {
    let path = format!("{}/tests/rooms/classroom_98.holo", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the room exists");
    let problem = first_room_problem(&path, &text);
    for solver in [solve::Solver::Dfs, solve::Solver::Milp] {
        let opts = SolveOptions { solver, ..SolveOptions::default() };
        let out = solve::solve_room(&problem, &opts).value;
        check_hard_rules(&problem, &out);
        assert_eq!(out.floor.len(), problem.objects.len(), "{solver:?}: {:?}", out.unplaced);
        let written = |c: &&solve::ConstraintReport| {
            !c.text.ends_with("(rows)") && !c.text.ends_with("(seating group)")
        };
        let all: usize =
            out.floor.iter().map(|p| p.constraints.iter().filter(written).count()).sum();
        let kept: usize = out
            .floor
            .iter()
            .map(|p| p.constraints.iter().filter(written).filter(|c| c.measure.satisfied).count())
            .sum();
        assert_eq!(all, 98, "the room's written relations");
        let placed = |id: &str| {
            let p = out.floor.iter().find(|p| problem.objects[p.index].id == id);
            p.unwrap_or_else(|| panic!("{id} placed ({solver:?})"))
        };
        for i in 0..10 {
            let desk = placed(&format!("student_desk-{i}"));
            let face = desk.constraints.iter().find(|c| c.text == "face to teacher_desk-0");
            assert!(face.is_some_and(|c| c.measure.satisfied), "{solver:?}: student_desk-{i}");
        }
        if solver == solve::Solver::Milp {
            continue;
        }
        assert!(kept >= 95, "{solver:?}: {kept} of {all} relations kept");
        for i in 0..10 {
            let desk = placed(&format!("student_desk-{i}"));
            let chair = placed(&format!("student_chair-{i}"));
            let gap = chair.footprint.gap(&desk.footprint);
            assert!(gap <= 0.6 + 1e-6, "student_chair-{i} is {gap:.2} m from its desk");
            assert!(solve::constraints::faces(&chair.pose, &desk.footprint), "student_chair-{i}");
        }
    }
}
