//! Building a [`RoomProblem`] from the checked [`Scene`].
//!
//! The floor plan (door keep-out zones, wall holes) and the resolved asset sizes come from the
//! `plan` and `resolve` stages; until they are wired in, callers pass the keep-out zones and
//! walls they have and a function that gives every object's size.

use super::{
    CeilingObject, FloorObject, Holder, Pose, ProblemConstraint, RoomProblem, Rot, SmallObject,
    WallObject, WallSegment,
};
use crate::check::scene::{GlobalKind, Object, ObjectId, Placement, RoomId, Scene, SmallItem};

/// Sizes `[width, depth, height]` in metres, as the asset resolver decided them.
pub trait Sizes {
    /// The size of a floor or wall object.
    fn object(&self, object: &Object) -> [f64; 3];
    /// The size of one copy of a small object.
    fn small(&self, item: &SmallItem) -> [f64; 3];
    /// The size of the room's ceiling object.
    fn ceiling(&self, room: RoomId) -> [f64; 3];
    /// The AI2-THOR object type of a floor or wall object's asset, when one is chosen.
    fn thor_type(&self, _object: &Object) -> Option<String> {
        None
    }
    /// Whether the object's asset can be made again at another size (an asset holoc made):
    /// curtains and blinds are then sized to the window they dress.
    fn resizable(&self, _object: &Object) -> bool {
        false
    }
}

/// Sizes from the scene alone: the written `size`, else 0.5 m × 0.5 m × 0.5 m; small objects
/// 0.2 m × 0.2 m × 0.2 m; ceiling objects 0.5 m × 0.5 m × 0.3 m.
#[derive(Clone, Copy, Debug, Default)]
pub struct WrittenSizes;

impl Sizes for WrittenSizes {
    fn object(&self, object: &Object) -> [f64; 3] {
        object.size_m.unwrap_or([0.5, 0.5, 0.5])
    }

    fn small(&self, _item: &SmallItem) -> [f64; 3] {
        [0.2, 0.2, 0.2]
    }

    fn ceiling(&self, _room: RoomId) -> [f64; 3] {
        [0.5, 0.5, 0.3]
    }
}

/// The layout problem of one room of a scene. `keep_out` and `walls` come from the floor plan
/// (empty: no door zones, walls from the outline without holes). Small objects are expanded to
/// `<item>-<i>` copies on their receptacle; pins (`at`, `facing`) become pinned poses.
pub fn room_problem(
    scene: &Scene,
    room: RoomId,
    sizes: &dyn Sizes,
    keep_out: Vec<Vec<[f64; 2]>>,
    walls: Vec<WallSegment>,
) -> RoomProblem {
    let r = scene.room(room);
    let floor_ids: Vec<ObjectId> =
        r.objects.iter().copied().filter(|id| scene.object(*id).is_floor()).collect();
    let index_of = |id: ObjectId| floor_ids.iter().position(|f| *f == id);
    let mut objects = Vec::new();
    let mut wall_objects = Vec::new();
    let mut small_objects = Vec::new();
    for &id in &r.objects {
        let o = scene.object(id);
        let size = sizes.object(o);
        match &o.placement {
            Placement::Floor { global, constraints } => {
                let pin = o.at.map(|[x, z]| Pose {
                    x,
                    z,
                    rot: Rot::from_deg(o.facing_deg.unwrap_or(0.0)),
                });
                objects.push(FloorObject {
                    id: o.name.clone(),
                    size: [size[0], size[1]],
                    height: size[2],
                    global: global.map_or(GlobalKind::Edge, |g| g.kind),
                    role: super::Role::of(&o.category),
                    constraints: constraints
                        .iter()
                        .filter_map(|c| {
                            index_of(c.target).map(|target| ProblemConstraint {
                                kind: c.kind,
                                written: c.kind,
                                implied: false,
                                target,
                                span: Some(c.span),
                            })
                        })
                        .collect(),
                    pin,
                    thor_type: sizes.thor_type(o),
                    span: Some(o.name_span),
                });
                let on = Holder::Floor(objects.len() - 1);
                small_objects.extend(items_on(o, on, sizes));
            }
            Placement::Wall { above, height_m } => {
                wall_objects.push(WallObject {
                    id: o.name.clone(),
                    size,
                    above: above.and_then(|(t, _)| index_of(t)),
                    height_m: *height_m,
                    thor_type: sizes.thor_type(o),
                    resizable: sizes.resizable(o),
                    span: Some(o.name_span),
                });
                let on = Holder::Wall(wall_objects.len() - 1);
                small_objects.extend(items_on(o, on, sizes));
            }
        }
    }
    super::read_meanings(&mut objects);
    RoomProblem {
        name: r.name.clone(),
        outline: r.corners.clone(),
        wall_height: scene.wall_height_m,
        keep_out,
        walls,
        objects,
        wall_objects,
        small_objects,
        ceiling: r.ceiling.as_ref().map(|c| CeilingObject {
            id: format!("ceiling ({})", r.name),
            size: sizes.ceiling(room),
            above: c.above.and_then(|(t, _)| index_of(t)),
            span: Some(c.span),
        }),
        span: Some(r.name_span),
    }
}

/// The ids the layout gives the copies of the items on top of an object (`book-0|shelf-0`),
/// with the `on top` line and the copy of each. Instances are numbered per item over every
/// line of the receptacle, so two lines naming the same item (an answer that repeats one)
/// never give two objects one id.
pub(crate) fn item_ids(o: &Object) -> Vec<(String, usize, u32)> {
    let mut next: std::collections::BTreeMap<&str, u32> = std::collections::BTreeMap::new();
    let mut out = Vec::new();
    for (k, item) in o.on_top.iter().enumerate() {
        for copy in 0..item.count {
            let n = next.entry(item.item.as_str()).or_insert(0);
            out.push((format!("{}-{n}|{}", item.item, o.name), k, copy));
            *n += 1;
        }
    }
    out
}

/// The copies of the items on top of object `o`, held by `on`.
fn items_on(o: &Object, on: Holder, sizes: &dyn Sizes) -> Vec<SmallObject> {
    item_ids(o)
        .into_iter()
        .map(|(id, k, _)| {
            let item = &o.on_top[k];
            SmallObject {
                id,
                item: item.item.clone(),
                size: sizes.small(item),
                on,
                elsewhere: None,
                absent: None,
                anchor: Vec::new(),
                thor_type: None,
                span: Some(item.span),
            }
        })
        .collect()
}
