//! The `resolve` stage: object descriptions → catalog assets.
//!
//! [`resolve`] chooses, for every object instance of a checked [`Scene`](crate::check::Scene), an asset of a
//! [`Catalog`]: a pinned one when the file pins it (checked for existence and placement kind),
//! otherwise the best-ranked asset of the right placement kind (see [`rank`] and the book's
//! `design/catalog-matching.md`). Small objects on top of receptacles and ceiling objects are
//! resolved the same way. An object nothing good enough matches is left out with a warning
//! naming its three nearest candidates, and is listed as unresolved; nothing is dropped silently.
//!
//! Doors, windows, materials and skyboxes are chosen by `resolve::structure`.

mod catalog;
pub mod colors;
mod errors;
mod index;
pub mod kinds;
mod material_words;
pub mod objathor;
mod placement;
pub mod receptacles;
mod report;
mod select;
pub mod standins;
pub mod structure;
mod text;

pub(crate) use catalog::sha256_hex;
pub use catalog::{Asset, Catalog, CatalogSource, PlacementKind, Placements, MAX_CATALOG_BYTES};
pub use index::{
    rank, rank_top, Candidate, Query, BM25_B, BM25_K1, HEAD_SHARE, RELEVANCE_THRESHOLD,
    RELEVANCE_WEIGHT, SIZE_WEIGHT,
};
pub use receptacles::{allowed_on, is_receptacle_type, receptacle_types};
pub use report::{candidate_json, report};
pub(crate) use select::parts_text;
pub use select::{
    assemble, resolve, resolve_cached, resolve_query, resolve_with, room_box, typical_on_object_m,
    Choice, RankCache, Resolution, ResolveOptions, Resolved, Resolver, RoomResolution, Unresolved,
    FLOOR_STANDING, MAX_SIZE_RATIO, ON_FURNITURE, ON_FURNITURE_TYPICAL_M, WALL_MOUNTED,
};

/// Ranks the catalog for a free-text query, as `holoc assets search` does: the whole text is
/// the category (its last word the head), with an optional desired size and placement kind.
/// Ties are broken with seed 0.
pub fn search(
    catalog: &Catalog,
    query: &str,
    size_m: Option<[f64; 3]>,
    kind: Option<PlacementKind>,
) -> Vec<Candidate> {
    let query = Query { category: query.to_string(), description: None, size_m, kind };
    rank(catalog, &query, 0)
}
