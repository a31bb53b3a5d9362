//! The parser: `.holo` text → [`ast::File`].
//!
//! The grammar (`grammar/holo.pest`) reads every block line by line and ends each block body
//! with a catch-all `bad_line`. The parser turns the pest tree into the AST; each bad line
//! becomes an [`ast::ErrorNode`] (so its text is kept) and one diagnostic, made by re-reading the
//! line with the rule its first word names (`errors.rs`).
//!
//! **Invariant:** pest types do not leave this module.

mod errors;
mod grammar;
mod relocate;

use crate::ast::{self, Ident, Quantity, Str, Unit};
use crate::diag::{Code, Diagnostic, Outcome};
use crate::source::{FileId, SourceMap, Span};
use grammar::{HoloParser, Rule};
use pest::iterators::Pair;
use pest::Parser as _;
use std::fmt::Write as _;
use std::ops::ControlFlow;

/// The block a line belongs to; it decides which statements may start the line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Context {
    /// The top level of the file.
    Top,
    /// A `scene` block.
    Scene,
    /// A `room` block.
    Room,
    /// An `object`, `wall object`, `instance`, `on top` or `ceiling` block.
    Object,
}

/// Parses the file `file` of `sources`.
///
/// Nothing is kept for a next parse: each piece is moved into the tree, so the tree is the
/// only copy of the items (keeping them, as [`parse_cached`] does for an editor, doubled the
/// memory of a large file).
pub fn parse(sources: &SourceMap, file: FileId) -> Outcome<ast::File> {
    parse_cut(sources, file, &mut ParseCache::default(), false)
}

/// Top-level items already parsed, by their text, with spans relative to their start: what the
/// language server keeps between keystrokes so that only the item being edited is parsed again.
#[derive(Clone, Debug, Default)]
pub struct ParseCache {
    chunks: rustc_hash::FxHashMap<String, std::rc::Rc<Chunk>>,
    /// Room statement groups by their text.
    groups: GroupMap,
    /// The last text cut into pieces, with where each piece is in its tree: what
    /// [`parse_edited`] edits in place.
    last: Option<LastCut>,
    /// How many trees were made by cutting the text into pieces.
    generation: u64,
    /// The number ([`ParseCache::generation`]) of the tree the last parse gave, when it was
    /// cut into pieces.
    tree: Option<u64>,
    /// What the last parse, when it edited a tree in place, replaced.
    splice: Option<Splice>,
}

/// What [`parse_edited`] replaced in a tree: the items of bytes `start..old_end` of the old
/// text became those of `start..new_end` of the new one; every item before is the same, every
/// item after the same but for its spans, moved by the change in length (and whether a blank
/// line is kept before the first of them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Splice {
    /// The number of the tree edited ([`ParseCache::tree_number`] when it was made).
    pub from: u64,
    /// Where the pieces replaced start.
    pub start: usize,
    /// Where they ended in the old text.
    pub old_end: usize,
    /// Where the new ones end in the new text.
    pub new_end: usize,
    /// When the edit was made inside one room's body: the statement groups of that body it
    /// replaced (see [`BodySplice`]); every statement of the room outside them is the same.
    pub body: Option<BodySplice>,
}

/// The statement groups of one room's body an edit replaced: those of bytes `start..old_end`
/// of the old text became those of `start..new_end` of the new one. Every statement of the
/// room that starts before `start` is the same; every one that started at or after `old_end`
/// the same but for its spans, moved by the change in length (blank lines aside). A group is a
/// statement that begins a line with its comments and blank lines after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BodySplice {
    /// Where the room starts (in both texts).
    pub room_start: usize,
    /// Where the groups replaced start.
    pub start: usize,
    /// Where they ended in the old text.
    pub old_end: usize,
    /// Where the new ones end in the new text.
    pub new_end: usize,
    /// How many groups were replaced, and by how many.
    pub old_groups: usize,
    pub new_groups: usize,
}

impl ParseCache {
    /// A number for the tree the last parse gave when it was cut into pieces (an edited tree
    /// gets a new one), `None` when it was parsed whole.
    pub fn tree_number(&self) -> Option<u64> {
        self.tree
    }

    /// What the last parse replaced, when it edited a tree in place.
    pub fn splice(&self) -> Option<Splice> {
        self.splice
    }

    /// Hands back the tree [`parse_edited`] made of `text`, for the next version to be made from
    /// it in place (a tree of another text is dropped); whether it was taken.
    pub fn give_back(&mut self, tree: ast::File, text: &str) -> bool {
        match &mut self.last {
            Some(last) if last.tree.is_none() && self.tree.is_some() && *last.text == *text => {
                last.tree = Some(tree);
                true
            }
            _ => false,
        }
    }
}

/// A text cut into top-level pieces, and what each piece put into its tree.
#[derive(Clone, Debug)]
struct LastCut {
    /// (Shared with the source file it was given: not a copy.)
    text: std::sync::Arc<String>,
    pieces: Vec<Piece>,
    /// The parse's diagnostics, the pieces' in order.
    diagnostics: Vec<Diagnostic>,
    /// The tree, once handed back ([`ParseCache::give_back`]).
    tree: Option<ast::File>,
    /// How many tokens the text holds ([`count_tokens`]), once counted: an edit inside a
    /// room's body counts the tokens of the statement groups it replaced, not the text's.
    tokens: Option<usize>,
}

/// One top-level piece of a [`LastCut`].
#[derive(Clone, Debug)]
struct Piece {
    /// Where it starts in the text.
    start: usize,
    /// How many items of the tree are its own, the blank line kept before it included.
    items: usize,
    /// Whether the first of them is that blank line.
    blank: bool,
    /// How many of the parse's diagnostics are its own.
    diagnostics: usize,
    /// For a room parsed group by group, its groups' texts (keys of the cache's groups).
    groups: Vec<std::rc::Rc<str>>,
}

/// One top-level piece of text, parsed on its own.
#[derive(Debug)]
struct Chunk {
    items: Vec<ast::Item>,
    diagnostics: Vec<Diagnostic>,
    /// For a room parsed group by group: the groups' texts (keys of [`ParseCache`]'s groups).
    groups: Vec<std::rc::Rc<str>>,
}

/// Parses the file, reusing the items of `cache` whose text has not changed.
///
/// The text is cut before every line that starts, outside any block, string or comment, with a
/// letter (`scene`, `room`, `door`, or a line that is none of these); each piece is parsed on its
/// own and its spans moved into place. The result is the one parsing the whole text at once
/// gives (the grammar reads the top level item by item); when the cut cannot be made safely (a
/// brace that closes nothing, a block or comment left open, a string that runs to the end of
/// its line) or a piece does not parse on its own, the whole text is parsed at once.
pub fn parse_cached(
    sources: &SourceMap,
    file: FileId,
    cache: &mut ParseCache,
) -> Outcome<ast::File> {
    parse_cut(sources, file, cache, true)
}

/// [`parse_cached`]; with `keep` false, the pieces are moved into the tree instead of kept
/// for the next parse (no piece is looked up either: the cache holds none).
fn parse_cut(
    sources: &SourceMap,
    file: FileId,
    cache: &mut ParseCache,
    keep: bool,
) -> Outcome<ast::File> {
    let text = &sources.get(file).text;
    cache.tree = None;
    cache.splice = None;
    if let Some(too_deep) = too_deep(sources, file) {
        return too_deep;
    }
    let Some(starts) = chunk_starts(text) else { return parse_whole(sources, file) };
    // The pieces of the last parse are moved (their texts too) into what this one keeps.
    let mut earlier = std::mem::take(&mut cache.chunks);
    let mut used: rustc_hash::FxHashMap<String, std::rc::Rc<Chunk>> =
        rustc_hash::FxHashMap::default();
    let mut used_groups = GroupMap::default();
    let mut tree = CutTree::default();
    tree.items.reserve_exact(starts.len());
    let mut pieces = Vec::with_capacity(starts.len());
    for (k, &start) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(text.len());
        let piece = &text[start..end];
        if !keep {
            let Some(chunk) = parse_piece_cached(piece, &cache.groups, &mut used_groups) else {
                return parse_whole(sources, file);
            };
            let Chunk { items: piece_items, diagnostics: piece_diagnostics, groups: _ } = chunk;
            pieces.push(tree.place(text, file, start, piece_items, piece_diagnostics));
            continue;
        }
        let (key, chunk) = match used.get(piece) {
            Some(hit) => (None, std::rc::Rc::clone(hit)),
            None => match earlier.remove_entry(piece) {
                Some((key, hit)) => {
                    // A room served whole keeps its statement groups for its next edit.
                    for key in &hit.groups {
                        if let Some(group) = cache.groups.get(key) {
                            used_groups.insert(std::rc::Rc::clone(key), std::rc::Rc::clone(group));
                        }
                    }
                    (Some(key), hit)
                }
                None => match parse_piece_cached(piece, &cache.groups, &mut used_groups) {
                    Some(chunk) => (Some(piece.to_string()), std::rc::Rc::new(chunk)),
                    None => {
                        // Kept for the next version, which may be cut again.
                        earlier.extend(used);
                        cache.chunks = earlier;
                        return parse_whole(sources, file);
                    }
                },
            },
        };
        pieces.push(tree.place(text, file, start, chunk.items.clone(), chunk.diagnostics.clone()));
        if let Some(key) = key {
            used.insert(key, chunk);
        }
    }
    // Only what the text still holds is kept. The rooms' statement groups are not (the pieces
    // are placed without them): they are a second copy of every room's statements, and what
    // they save is parsing a room's other statements again at its next edit, which only the
    // rooms being edited need ([`parse_edited`] keeps the groups of the rooms it parses again).
    drop(used_groups);
    let CutTree { items, diagnostics, .. } = tree;
    cache.chunks = used;
    cache.groups = GroupMap::default();
    cache.last = Some(LastCut {
        text: std::sync::Arc::clone(text),
        pieces,
        diagnostics: diagnostics.clone(),
        tree: None,
        tokens: None,
    });
    cache.generation += 1;
    cache.tree = Some(cache.generation);
    Outcome::new(ast::File { items, span: Span::new(file, 0, text.len()) }, diagnostics)
}

/// The tree [`parse_cut`] puts together from its pieces: the items, the diagnostics, and where
/// the items placed so far end (for the blank line kept before the next piece).
#[derive(Default)]
struct CutTree {
    items: Vec<ast::Item>,
    diagnostics: Vec<Diagnostic>,
    previous_end: Option<usize>,
}

impl CutTree {
    /// Puts the items and diagnostics of a piece parsed on its own where the piece starts in
    /// the text, with the blank line kept before it; its [`Piece`], without statement groups.
    fn place(
        &mut self,
        text: &str,
        file: FileId,
        start: usize,
        mut piece_items: Vec<ast::Item>,
        mut piece_diagnostics: Vec<Diagnostic>,
    ) -> Piece {
        let (items_before, diagnostics_before) = (self.items.len(), self.diagnostics.len());
        let m = relocate::Move::shift(file, start as i64);
        relocate::Relocate::relocate(&mut piece_items, m);
        let blank = blank_before(text, file, self.previous_end, &piece_items);
        self.items.extend(blank.clone());
        self.previous_end =
            piece_items.last().map(|i| item_span(i).end as usize).or(self.previous_end);
        self.items.extend(piece_items);
        relocate::Relocate::relocate(&mut piece_diagnostics, m);
        self.diagnostics.extend(piece_diagnostics);
        Piece {
            start,
            items: self.items.len() - items_before,
            blank: blank.is_some(),
            diagnostics: self.diagnostics.len() - diagnostics_before,
            groups: Vec::new(),
        }
    }
}

/// The blank line kept before a piece's items: when the text between the end of the items
/// before (`previous_end`) and its first item holds an empty line.
fn blank_before(
    text: &str,
    file: FileId,
    previous_end: Option<usize>,
    piece_items: &[ast::Item],
) -> Option<ast::Item> {
    let (end, first) = (previous_end?, piece_items.first()?);
    let first_start = item_span(first).start as usize;
    text.get(end..first_start)
        .is_some_and(|gap| gap.matches('\n').count() >= 2)
        .then(|| ast::Item::Blank(Span::new(file, first_start, first_start)))
}

/// Parses the file as [`parse_cached`] does (the same tree and diagnostics), but when the tree of
/// the last text cut into pieces was handed back ([`ParseCache::give_back`]), edits it in place:
/// the text between the two versions' common prefix and suffix is cut again from the start of
/// the piece it begins in until a cut falls where one fell before, those pieces are parsed (a
/// room by its statement groups, with the cache), put in the place of the old ones, and the
/// items after them moved by the change in length. Nothing else of the tree is copied or read.
/// Where that cannot be done (no tree handed back, a cut that is not safe, a piece that does not
/// parse alone, braces too deep) it parses as [`parse_cached`] does, and it keeps no whole copy
/// of the pieces between versions (the statement groups of rooms are kept by text).
pub fn parse_edited(
    sources: &SourceMap,
    file: FileId,
    cache: &mut ParseCache,
) -> Outcome<ast::File> {
    let text = &sources.get(file).text;
    if let Some(last) = &mut cache.last {
        if let Some(mut tree) = last.tree.take() {
            if let Some((start, old_end, new_end, body)) =
                splice(text, file, last, &mut cache.groups, &mut tree)
            {
                let diagnostics = last.diagnostics.clone();
                let from = cache.generation;
                cache.generation += 1;
                cache.tree = Some(cache.generation);
                cache.splice = Some(Splice { from, start, old_end, new_end, body });
                return Outcome::new(tree, diagnostics);
            }
            // Kept for the next version, which may be cut again.
            last.tree = Some(tree);
        }
    }
    // The pieces are moved into the tree the caller hands back; a second copy is not kept.
    cache.chunks = rustc_hash::FxHashMap::default();
    parse_cut(sources, file, cache, false)
}

/// Edits `tree`, the tree of `last.text`, into the tree of `text` (see [`parse_edited`]), with
/// `last` then describing `text`: the bytes of the pieces replaced in the old text and the new
/// one (`start`, `old_end`, `new_end`) and, for an edit inside a room's body, the statement
/// groups replaced; or `None` (with nothing changed) when it cannot.
fn splice(
    text: &std::sync::Arc<String>,
    file: FileId,
    last: &mut LastCut,
    groups: &mut GroupMap,
    tree: &mut ast::File,
) -> Option<(usize, usize, usize, Option<BodySplice>)> {
    let old_len = last.text.len();
    let (start, old_end, new_end) = crate::source::changed_range(&last.text, text);
    if start == old_end && start == new_end {
        return Some((0, 0, 0, None));
    }
    if last.pieces.first().is_none_or(|p| p.start != 0) {
        return None;
    }
    // The piece the edit starts in (a cut at the edit's start may no longer be one: the piece
    // before it is cut again too, unless the edit starts the text).
    let k0 = last.pieces.partition_point(|p| p.start < start).saturating_sub(1);
    let edit = (start, old_end, new_end);
    if let Some(body) = splice_in_body(text, file, last, groups, tree, k0, edit) {
        return Some((
            last.pieces[k0].start,
            body.old_piece_end,
            body.new_piece_end,
            Some(body.splice),
        ));
    }
    last.tokens = None;
    let pieces = &last.pieces;
    let s0 = pieces[k0].start;
    // A cut of the new text at or after the edit's end where the old text had one: from there
    // the scan goes as it went then.
    let resync = |i: usize| {
        let o = i - new_end + old_end;
        pieces.binary_search_by_key(&o, |p| p.start).ok().filter(|&k| k >= k0)
    };
    let (starts, k1) = cut_from(text, s0, new_end, resync)?;
    let region_end = k1.map_or(text.len(), |k| pieces[k].start - old_end + new_end);
    let old_region_end = k1.map_or(old_len, |k| pieces[k].start);
    let k1 = k1.unwrap_or(pieces.len());
    if first_too_deep(&text[s0..region_end]).is_some() || first_token_past_limit(text).is_some() {
        return None;
    }
    // Parse the new pieces before anything is changed (a room edited inside its body, in
    // place: its spans are then the text's, not the piece's).
    let mut used = GroupMap::default();
    let mut chunks = Vec::with_capacity(starts.len());
    let i0: usize = pieces[..k0].iter().map(|p| p.items).sum();
    let in_body = (starts.len() == 1 && k1 == k0 + 1)
        .then(|| {
            let piece = &pieces[k0];
            let at = i0 + usize::from(piece.blank);
            let ast::Item::Room(room) = tree.items.get_mut(at)? else { return None };
            let edit = BodyEdit {
                old_piece: &last.text[s0..old_region_end],
                new_piece: &text[s0..region_end],
                text,
                file,
                piece_start: s0,
                edit: (start, old_end),
            };
            let (keys, body) = edit.apply(piece, room, groups, &mut used)?;
            let room = std::mem::replace(&mut tree.items[at], ast::Item::Blank(Span::default()));
            Some((Chunk { items: vec![room], diagnostics: Vec::new(), groups: keys }, body))
        })
        .flatten();
    let absolute = in_body.is_some();
    let mut body_splice = None;
    match in_body {
        Some((chunk, body)) => {
            body_splice = Some(body);
            chunks.push((s0, chunk));
        }
        None => {
            for (k, &at) in starts.iter().enumerate() {
                let end = starts.get(k + 1).copied().unwrap_or(region_end);
                chunks.push((at, parse_piece_cached(&text[at..end], groups, &mut used)?));
            }
        }
    }
    let delta = new_end as i64 - old_end as i64;
    let i1: usize = i0 + pieces[k0..k1].iter().map(|p| p.items).sum::<usize>();
    let d0: usize = pieces[..k0].iter().map(|p| p.diagnostics).sum();
    let d1: usize = d0 + pieces[k0..k1].iter().map(|p| p.diagnostics).sum::<usize>();
    // The new pieces' items and diagnostics, in place.
    let mut previous_end = tree.items[..i0].last().map(|i| item_span(i).end as usize);
    let mut new_items = Vec::new();
    let mut new_diagnostics = Vec::new();
    let mut new_pieces = Vec::with_capacity(chunks.len());
    for (at, chunk) in chunks {
        let m = relocate::Move::shift(file, at as i64);
        let mut piece_items = chunk.items;
        if !absolute {
            relocate::Relocate::relocate(&mut piece_items, m);
        }
        let blank = blank_before(text, file, previous_end, &piece_items);
        let (items_before, diagnostics_before) = (new_items.len(), new_diagnostics.len());
        let has_blank = blank.is_some();
        new_items.extend(blank);
        previous_end = piece_items.last().map(|i| item_span(i).end as usize).or(previous_end);
        new_items.extend(piece_items);
        let mut piece_diagnostics = chunk.diagnostics;
        relocate::Relocate::relocate(&mut piece_diagnostics, m);
        new_diagnostics.extend(piece_diagnostics);
        new_pieces.push(Piece {
            start: at,
            items: new_items.len() - items_before,
            blank: has_blank,
            diagnostics: new_diagnostics.len() - diagnostics_before,
            groups: chunk.groups,
        });
    }
    // The statement groups of the pieces replaced leave the cache, those of the new ones come.
    for piece in &pieces[k0..k1] {
        for key in &piece.groups {
            if !used.contains_key(key) {
                groups.remove(key);
            }
        }
    }
    groups.extend(used);
    let n_new_items = new_items.len();
    let _ = tree.items.splice(i0..i1, new_items);
    let _ = last.diagnostics.splice(d0..d1, new_diagnostics);
    if delta != 0 {
        let m = relocate::Move::shift(file, delta);
        for item in &mut tree.items[i0 + n_new_items..] {
            relocate::Relocate::relocate(item, m);
        }
        let d_after = d0 + new_pieces.iter().map(|p| p.diagnostics).sum::<usize>();
        for d in &mut last.diagnostics[d_after..] {
            relocate::Relocate::relocate(d, m);
        }
    }
    let n_new_pieces = new_pieces.len();
    let _ = last.pieces.splice(k0..k1, new_pieces);
    for piece in &mut last.pieces[k0 + n_new_pieces..] {
        piece.start = (piece.start as i64 + delta) as usize;
    }
    // The blank lines kept before the pieces after the edit: the text before them changed.
    let mut at = i0 + n_new_items;
    for piece in &mut last.pieces[k0 + n_new_pieces..] {
        let previous_end = tree.items[..at].last().map(|i| item_span(i).end as usize);
        if piece.blank {
            tree.items.remove(at);
            piece.items -= 1;
        }
        let own = &tree.items[at..at + piece.items];
        let blank = blank_before(text, file, previous_end, own);
        piece.blank = blank.is_some();
        if let Some(blank) = blank {
            tree.items.insert(at, blank);
            piece.items += 1;
        }
        // A piece with items decides the previous end of every later one, which did not move.
        if piece.items > 0 {
            break;
        }
        at += piece.items;
    }
    tree.span = Span::new(file, 0, text.len());
    last.text = std::sync::Arc::clone(text);
    Some((s0, old_region_end, region_end, body_splice))
}

/// What [`splice_in_body`] did: the statement groups it replaced, and where the room's piece
/// ended in the old text and ends in the new one.
struct InBody {
    splice: BodySplice,
    old_piece_end: usize,
    new_piece_end: usize,
}

/// [`splice`] for an edit inside the body of a room whose statement groups the last parse kept
/// (its piece's `groups`, which tile its body): the groups around the edit alone are cut again
/// (from the last group start before the edit to the first after it), checked for depth and
/// counted, parsed with the cache and put in the room in place; nothing else of the room or
/// the text is scanned. `None`, with nothing changed, when the edit is not so or the groups
/// cut again do not close where they began (a brace or quote left open, a block comment over
/// lines): then the room's piece is cut again whole.
fn splice_in_body(
    text: &std::sync::Arc<String>,
    file: FileId,
    last: &mut LastCut,
    groups: &mut GroupMap,
    tree: &mut ast::File,
    k0: usize,
    (start, old_end, new_end): (usize, usize, usize),
) -> Option<InBody> {
    let piece = last.pieces.get(k0)?;
    if piece.groups.is_empty()
        || piece.diagnostics != 0
        || piece.items != 1 + usize::from(piece.blank)
    {
        return None;
    }
    let s0 = piece.start;
    let old_piece_end = last.pieces.get(k0 + 1).map_or(last.text.len(), |p| p.start);
    // The body: after the room's first `{` (in its header, before any group), tiled by the
    // groups.
    let open = s0 + first_open_brace(last.text.get(s0..old_piece_end)?)?;
    let body_start = open + 1;
    let mut starts = Vec::with_capacity(piece.groups.len() + 1);
    let mut at = body_start;
    for key in &piece.groups {
        starts.push(at);
        at += key.len();
    }
    let body_end = at;
    starts.push(body_end);
    debug_assert!(
        piece.groups.iter().zip(&starts).all(|(k, &a)| last.text.get(a..a + k.len()) == Some(&**k)),
        "the groups tile the body"
    );
    if last.text.as_bytes().get(body_end) != Some(&b'}') || start <= open || old_end > body_end {
        return None;
    }
    // The groups cut again: from the last group start before the edit (the first group if
    // none) to the first group start after its end (the body's end if none), so that the text
    // before and after them is the same in both versions and their first and last cuts stand.
    let n_old = piece.groups.len();
    let a = starts[..n_old].partition_point(|&g| g < start).saturating_sub(1);
    let b = starts[..n_old].partition_point(|&g| g <= old_end).max(a + 1);
    let (region_start, old_region_end) = (starts[a], starts[b]);
    let new_region_end = (old_region_end + new_end).checked_sub(old_end)?;
    let new_region = text.get(region_start..new_region_end)?;
    let old_region = last.text.get(region_start..old_region_end)?;
    // Its first and last cuts stand: a line that starts with a letter where a group began (the
    // body's first group starts at its start whatever it holds), a line's end where one ended
    // (but at the body's end).
    let letter_first = new_region
        .bytes()
        .find(|c| !matches!(c, b' ' | b'\t'))
        .is_some_and(|c| c.is_ascii_alphabetic());
    if a > 0 && !letter_first || b < n_old && !new_region.ends_with('\n') {
        return None;
    }
    // The new groups' starts: the region must close where it began (no brace of the room
    // closed, none left open, no string or comment left open).
    let mut new_starts = vec![0];
    scan_cuts(new_region, 0, true, |i| {
        new_starts.push(i);
        ControlFlow::Continue(())
    })?;
    // The room's body is one level deep: the region may nest one level less.
    if first_too_deep_from(new_region, 1).is_some() {
        return None;
    }
    let tokens = match last.tokens {
        Some(t) => t,
        None => count_tokens(&last.text),
    };
    let tokens =
        tokens.checked_sub(count_tokens(old_region))?.checked_add(count_tokens(new_region))?;
    if tokens > MAX_TOKENS {
        return None;
    }
    // Parse the new groups (with the cache) before anything is changed.
    let mut parsed: Vec<(std::rc::Rc<str>, std::rc::Rc<Group>)> =
        Vec::with_capacity(new_starts.len());
    for (k, &from) in new_starts.iter().enumerate() {
        let to = new_starts.get(k + 1).copied().unwrap_or(new_region.len());
        let group_text = &new_region[from..to];
        let (key, group) = match groups.get_key_value(group_text) {
            Some((key, hit)) => (std::rc::Rc::clone(key), std::rc::Rc::clone(hit)),
            None => (std::rc::Rc::from(group_text), std::rc::Rc::new(parse_group(group_text)?)),
        };
        if !group.diagnostics.is_empty() {
            return None;
        }
        parsed.push((key, group));
    }
    // The room: the piece's last item.
    let i_room =
        last.pieces[..k0].iter().map(|p| p.items).sum::<usize>() + usize::from(piece.blank);
    let Some(ast::Item::Room(room)) = tree.items.get_mut(i_room) else { return None };
    let room_start = room.span.start as usize;
    // Nothing fails from here on.
    let delta = new_end as i64 - old_end as i64;
    let first_of = |room: &ast::Room, g: usize| {
        room.body.partition_point(|st| (room_stmt_span(st).start as usize) < g)
    };
    let (i_p, i_s) = (first_of(room, region_start), first_of(room, old_region_end));
    let mut body = std::mem::take(&mut room.body);
    let suffix = body.split_off(i_s);
    let _ = body.split_off(i_p);
    let placed =
        parsed.iter().zip(&new_starts).map(|((_, group), &from)| (&**group, region_start + from));
    room.body = splice_body(text, file, body, placed, suffix, delta);
    room.span.end = (i64::from(room.span.end) + delta) as u32;
    // The items and diagnostics after the room move.
    if delta != 0 {
        let m = relocate::Move::shift(file, delta);
        for item in &mut tree.items[i_room + 1..] {
            relocate::Relocate::relocate(item, m);
        }
        let d_after: usize = last.pieces[..=k0].iter().map(|p| p.diagnostics).sum();
        for d in &mut last.diagnostics[d_after..] {
            relocate::Relocate::relocate(d, m);
        }
        for p in &mut last.pieces[k0 + 1..] {
            p.start = (p.start as i64 + delta) as usize;
        }
    }
    tree.span = Span::new(file, 0, text.len());
    // The piece's groups, and the cache's: the groups replaced leave it (unless a new one has
    // the same text), the new ones come.
    let b_new = a + parsed.len();
    let old_keys: Vec<std::rc::Rc<str>> = {
        let keys = &mut last.pieces[k0].groups;
        let new_keys = parsed.iter().map(|(key, _)| std::rc::Rc::clone(key));
        keys.splice(a..b, new_keys).collect()
    };
    for key in &old_keys {
        if !parsed.iter().any(|(k, _)| **k == **key) {
            groups.remove(key);
        }
    }
    for (key, group) in parsed {
        groups.insert(key, group);
    }
    last.text = std::sync::Arc::clone(text);
    last.tokens = Some(tokens);
    let new_piece_end = (old_piece_end as i64 + delta) as usize;
    Some(InBody {
        splice: BodySplice {
            room_start,
            start: region_start,
            old_end: old_region_end,
            new_end: new_region_end,
            old_groups: b - a,
            new_groups: b_new - a,
        },
        old_piece_end,
        new_piece_end,
    })
}

/// Where the first `{` of a piece is, outside strings and comments.
fn first_open_brace(piece: &str) -> Option<usize> {
    let bytes = piece.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => return Some(i),
            b'}' => return None,
            b'"' | b'/' => match literal_at(piece, i) {
                Literal::EndsAt(end) => i = end,
                Literal::Uncuttable => return None,
                Literal::Neither => {}
            },
            _ => {}
        }
        i += 1;
    }
    None
}

fn item_span(item: &ast::Item) -> Span {
    match item {
        ast::Item::Scene(x) => x.span,
        ast::Item::Room(x) => x.span,
        ast::Item::Door(x) => x.span,
        ast::Item::Comment(x) => x.span,
        ast::Item::Blank(x) => *x,
        ast::Item::Error(x) => x.span,
    }
}

/// Room statement groups by their text.
type GroupMap = rustc_hash::FxHashMap<std::rc::Rc<str>, std::rc::Rc<Group>>;

/// The text a synthetic room header puts before a group of room statements parsed alone.
const GROUP_PREFIX: &str = "room r {";

/// Parses one top-level piece: a room statement group by statement group (each group kept in
/// `cache` by its text, so that a large room's unchanged objects are not parsed again), any
/// other piece at once.
fn parse_piece_cached(piece: &str, cache: &GroupMap, used: &mut GroupMap) -> Option<Chunk> {
    if piece.starts_with("room") {
        if let Some(chunk) = parse_room_by_groups(piece, cache, used) {
            return Some(chunk);
        }
    }
    parse_piece(piece)
}

/// A room piece edited inside its body: the old and new texts of the piece, the whole new
/// text, where the piece starts and where the edit starts and ended in the old text.
struct BodyEdit<'a> {
    old_piece: &'a str,
    new_piece: &'a str,
    text: &'a str,
    file: FileId,
    piece_start: usize,
    edit: (usize, usize),
}

impl BodyEdit<'_> {
    /// Edits `room`, the tree's room of the old piece (parsed by its statement groups, the
    /// texts of which `piece` keeps), into the room of the new piece: the groups the two
    /// bodies begin and end with keep their statements (moved by the change in length after
    /// the edit), the groups between are parsed (with the cache) and put between them, and
    /// the blank lines kept where they meet are made again. `None`, with nothing changed, when
    /// the edit is not inside the body, the room or a group between has a diagnostic, or the
    /// piece holds more than the room. The new groups' texts, in order (each in `used`), and
    /// the groups replaced.
    fn apply(
        &self,
        piece: &Piece,
        room: &mut ast::Room,
        groups: &GroupMap,
        used: &mut GroupMap,
    ) -> Option<(Vec<std::rc::Rc<str>>, BodySplice)> {
        if piece.groups.is_empty()
            || piece.diagnostics != 0
            || piece.items != 1 + usize::from(piece.blank)
        {
            return None;
        }
        let (open, close) = outer_braces(self.old_piece)?;
        let (new_open, new_close) = outer_braces(self.new_piece)?;
        let (edit_start, edit_end) = (
            self.edit.0.checked_sub(self.piece_start)?,
            self.edit.1.checked_sub(self.piece_start)?,
        );
        let delta = self.new_piece.len() as i64 - self.old_piece.len() as i64;
        if new_open != open
            || edit_start <= open
            || edit_end > close
            || new_close as i64 != close as i64 + delta
        {
            return None;
        }
        let old_body = &self.old_piece[open + 1..close];
        let new_body = &self.new_piece[open + 1..new_close];
        // The old groups' starts in the old body: their texts cut it.
        let mut old_starts = Vec::with_capacity(piece.groups.len() + 1);
        let mut at = 0;
        for key in &piece.groups {
            if old_body.get(at..at + key.len()) != Some(&**key) {
                return None;
            }
            old_starts.push(at);
            at += key.len();
        }
        if at != old_body.len() {
            return None;
        }
        old_starts.push(at);
        let new_starts = body_starts(new_body)?;
        let new_group = |k: usize| {
            let end = new_starts.get(k + 1).copied().unwrap_or(new_body.len());
            &new_body[new_starts[k]..end]
        };
        let (n_old, n_new) = (piece.groups.len(), new_starts.len());
        let same = n_old.min(n_new);
        let p = (0..same).take_while(|&k| *piece.groups[k] == *new_group(k)).count();
        let s = (0..same - p)
            .take_while(|&j| *piece.groups[n_old - 1 - j] == *new_group(n_new - 1 - j))
            .count();
        // Every group's parse, from the cache (the groups kept) or parsed now (those between).
        let kept = |key: &std::rc::Rc<str>| {
            groups
                .get_key_value(&**key)
                .or_else(|| used.get_key_value(&**key))
                .map(|(k, g)| (std::rc::Rc::clone(k), std::rc::Rc::clone(g)))
        };
        let mut parsed: Vec<(std::rc::Rc<str>, std::rc::Rc<Group>)> = Vec::with_capacity(n_new);
        for k in 0..n_new {
            let found = if k < p {
                kept(&piece.groups[k])
            } else if k >= n_new - s {
                kept(&piece.groups[k + n_old - n_new])
            } else {
                let text = new_group(k);
                match groups.get_key_value(text).or_else(|| used.get_key_value(text)) {
                    Some((key, hit)) => Some((std::rc::Rc::clone(key), std::rc::Rc::clone(hit))),
                    None => Some((std::rc::Rc::from(text), std::rc::Rc::new(parse_group(text)?))),
                }
            };
            let (key, group) = found?;
            if !group.diagnostics.is_empty() {
                return None;
            }
            parsed.push((key, group));
        }
        // The statements of the groups kept: those before group `p`, and from group
        // `n_old - s` on (a statement belongs to the group its span starts in).
        let body_start = self.piece_start + open + 1;
        let first_of = |g: usize| {
            let at = (body_start + old_starts[g]) as u32;
            room.body.partition_point(|st| room_stmt_span(st).start < at)
        };
        let (i_p, i_s) = (first_of(p), first_of(n_old - s));
        // Nothing fails from here on.
        let mut body = std::mem::take(&mut room.body);
        let suffix = body.split_off(i_s);
        body.truncate(i_p);
        let placed = parsed
            .iter()
            .enumerate()
            .take(n_new - s)
            .skip(p)
            .map(|(k, (_, group))| (&**group, body_start + new_starts[k]));
        room.body = splice_body(self.text, self.file, body, placed, suffix, delta);
        room.span.end = (i64::from(room.span.end) + delta) as u32;
        let mut keys = Vec::with_capacity(parsed.len());
        for (key, group) in parsed {
            keys.push(std::rc::Rc::clone(&key));
            used.insert(key, group);
        }
        let new_at = |k: usize| new_starts.get(k).copied().unwrap_or(new_body.len());
        let body_splice = BodySplice {
            room_start: room.span.start as usize,
            start: body_start + old_starts[p],
            old_end: body_start + old_starts[n_old - s],
            new_end: body_start + new_at(n_new - s),
            old_groups: n_old - s - p,
            new_groups: n_new - s - p,
        };
        Some((keys, body_splice))
    }
}

/// A group of room statements parsed alone: statements and diagnostics with spans from the
/// group's start.
#[derive(Debug)]
struct Group {
    stmts: Vec<ast::RoomStmt>,
    diagnostics: Vec<Diagnostic>,
}

/// A room piece parsed as its header (with an empty body) and its body's statement groups, or
/// `None` when it cannot be cut that way.
fn parse_room_by_groups(piece: &str, cache: &GroupMap, used: &mut GroupMap) -> Option<Chunk> {
    let (open, close) = outer_braces(piece)?;
    let body = &piece[open + 1..close];
    let starts = body_starts(body)?;
    // The header: the room with an empty body, and what follows its `}` on the piece.
    let header = format!("{}}}{}", &piece[..=open], &piece[close + 1..]);
    let mut parsed = parse_piece(&header)?;
    let body_len = (close - open - 1) as i64;
    let after = |span: Span| span.start as usize > open;
    for (k, item) in parsed.items.iter_mut().enumerate() {
        if k == 0 {
            let ast::Item::Room(room) = item else { return None };
            if !room.body.is_empty() {
                return None;
            }
            room.span.end += body_len as u32;
        } else {
            relocate::Relocate::relocate(item, relocate::Move::shift(FileId(0), body_len));
        }
    }
    for d in &mut parsed.diagnostics {
        if d.primary.as_ref().is_some_and(|p| after(p.span)) {
            relocate::Relocate::relocate(d, relocate::Move::shift(FileId(0), body_len));
        }
    }
    let mut stmts: Vec<ast::RoomStmt> = Vec::new();
    let mut diagnostics = Vec::new();
    let mut keys = Vec::with_capacity(starts.len());
    let mut previous_end: Option<usize> = None;
    for (k, &start) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(body.len());
        let text = &body[start..end];
        let (key, group) = match cache.get_key_value(text).or_else(|| used.get_key_value(text)) {
            Some((key, hit)) => (std::rc::Rc::clone(key), std::rc::Rc::clone(hit)),
            None => (std::rc::Rc::from(text), std::rc::Rc::new(parse_group(text)?)),
        };
        let m =
            relocate::Move::shift(FileId(0), (open + 1 + start) as i64 - GROUP_PREFIX.len() as i64);
        let mut group_stmts = group.stmts.clone();
        relocate::Relocate::relocate(&mut group_stmts, m);
        if let (Some(end), Some(first)) = (previous_end, group_stmts.first()) {
            let first_start = room_stmt_span(first).start as usize;
            if piece.get(end..first_start).is_some_and(|gap| gap.matches('\n').count() >= 2) {
                stmts.push(ast::RoomStmt::Blank(Span::new(FileId(0), first_start, first_start)));
            }
        }
        previous_end = group_stmts.last().map(|s| room_stmt_span(s).end as usize).or(previous_end);
        stmts.extend(group_stmts);
        let mut group_diagnostics = group.diagnostics.clone();
        relocate::Relocate::relocate(&mut group_diagnostics, m);
        diagnostics.extend(group_diagnostics);
        keys.push(std::rc::Rc::clone(&key));
        used.insert(key, group);
    }
    if let Some(ast::Item::Room(room)) = parsed.items.first_mut() {
        room.body = stmts;
    }
    // The header's diagnostics come before the body's only if they are about the header.
    let (before, later): (Vec<Diagnostic>, Vec<Diagnostic>) = parsed
        .diagnostics
        .into_iter()
        .partition(|d| d.primary.as_ref().is_none_or(|p| (p.span.start as usize) <= open));
    let mut all = before;
    all.extend(diagnostics);
    all.extend(later);
    Some(Chunk { items: parsed.items, diagnostics: all, groups: keys })
}
/// A room's body made again after an edit: `body` (the statements before the groups parsed
/// again), each group's statements moved from its own text to where that text starts in the
/// file, then `suffix` (the statements after them) moved by `delta`, with the blank lines
/// between them read again from `text`.
fn splice_body<'g>(
    text: &str,
    file: FileId,
    mut body: Vec<ast::RoomStmt>,
    groups: impl IntoIterator<Item = (&'g Group, usize)>,
    mut suffix: Vec<ast::RoomStmt>,
    delta: i64,
) -> Vec<ast::RoomStmt> {
    let mut previous_end = body.last().map(|st| room_stmt_span(st).end as usize);
    let blank = |previous_end: Option<usize>, first: &ast::RoomStmt| {
        let first_start = room_stmt_span(first).start as usize;
        let end = previous_end?;
        text.get(end..first_start)
            .is_some_and(|gap| gap.matches('\n').count() >= 2)
            .then(|| ast::RoomStmt::Blank(Span::new(file, first_start, first_start)))
    };
    for (group, at) in groups {
        let m = relocate::Move::shift(file, at as i64 - GROUP_PREFIX.len() as i64);
        let mut group_stmts = group.stmts.clone();
        relocate::Relocate::relocate(&mut group_stmts, m);
        if let Some(first) = group_stmts.first() {
            body.extend(blank(previous_end, first));
        }
        previous_end =
            group_stmts.last().map(|st| room_stmt_span(st).end as usize).or(previous_end);
        body.extend(group_stmts);
    }
    if delta != 0 {
        relocate::Relocate::relocate(&mut suffix, relocate::Move::shift(file, delta));
    }
    // The blank line kept before the groups kept after the edit: the text before changed.
    if matches!(suffix.first(), Some(ast::RoomStmt::Blank(_))) {
        suffix.remove(0);
    }
    if let Some(first) = suffix.first() {
        body.extend(blank(previous_end, first));
    }
    body.extend(suffix);
    body
}

/// A group of room statements parsed inside a synthetic room header.
fn parse_group(text: &str) -> Option<Group> {
    let wrapped = format!("{GROUP_PREFIX}{text}}}");
    let chunk = parse_piece(&wrapped)?;
    let [ast::Item::Room(room)] = chunk.items.as_slice() else { return None };
    Some(Group { stmts: room.body.clone(), diagnostics: chunk.diagnostics })
}

/// The piece's first `{` and the `}` that closes it, outside strings and comments.
fn outer_braces(piece: &str) -> Option<(usize, usize)> {
    let bytes = piece.as_bytes();
    let mut depth = 0i64;
    let mut open = None;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => {
                open = open.or(Some(i));
                depth += 1;
            }
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return open.map(|o| (o, i));
                }
                if depth < 0 {
                    return None;
                }
            }
            b'"' | b'/' => match literal_at(piece, i) {
                Literal::EndsAt(end) => i = end,
                Literal::Uncuttable => return None,
                Literal::Neither => {}
            },
            _ => {}
        }
        i += 1;
    }
    None
}

fn room_stmt_span(stmt: &ast::RoomStmt) -> Span {
    match stmt {
        ast::RoomStmt::FloorDesign(_, s)
        | ast::RoomStmt::WallDesign(_, s)
        | ast::RoomStmt::FloorMaterial(_, s)
        | ast::RoomStmt::WallMaterial(_, s)
        | ast::RoomStmt::Blank(s) => *s,
        ast::RoomStmt::Corners(c) => c.span,
        ast::RoomStmt::Window(w) => w.span,
        ast::RoomStmt::Object(o) | ast::RoomStmt::WallObject(o) => o.span,
        ast::RoomStmt::Ceiling(c) => c.span,
        ast::RoomStmt::Comment(c) => c.span,
        ast::RoomStmt::Error(e) => e.span,
    }
}

/// Parses one top-level piece on its own (file 0, spans from its start), or `None` when it
/// does not parse as a whole or holds a brace that closes nothing.
fn parse_piece(piece: &str) -> Option<Chunk> {
    let mut pairs = HoloParser::parse(Rule::file, piece).ok()?;
    let file = FileId(0);
    let mut builder = Builder { file, text: piece, diagnostics: Vec::new() };
    let parsed = builder.file(pairs.next()?);
    if parsed.items.iter().any(|i| matches!(i, ast::Item::Error(e) if e.text == "}")) {
        return None;
    }
    Some(Chunk { items: parsed.items, diagnostics: builder.diagnostics, groups: Vec::new() })
}

/// Where each top-level piece starts: line starts outside any block, string and comment whose
/// first character is a letter (and 0). `None` when the braces, strings or comments of the text
/// do not allow a safe cut.
fn chunk_starts(text: &str) -> Option<Vec<usize>> {
    cut_points(text, false)
}

/// Where each statement group of a block body starts: 0, and the start of every line whose
/// first character after its indentation is a letter, outside any nested block, string and
/// comment. `None` as for [`chunk_starts`].
fn body_starts(body: &str) -> Option<Vec<usize>> {
    cut_points(body, true)
}

fn cut_points(text: &str, indented: bool) -> Option<Vec<usize>> {
    let mut starts = vec![0];
    scan_cuts(text, 0, indented, |i| {
        starts.push(i);
        ControlFlow::Continue(())
    })?;
    Some(starts)
}

/// The cuts of `text` from `from` (a cut) on, as [`chunk_starts`] makes them, until a cut at or
/// after `after` for which `resync` names the old piece starting there: the cuts before it and
/// that piece, or `None` as the last item when the scan reached the end. `None` when the text
/// from `from` does not allow a safe cut.
fn cut_from(
    text: &str,
    from: usize,
    after: usize,
    resync: impl Fn(usize) -> Option<usize>,
) -> Option<(Vec<usize>, Option<usize>)> {
    let mut starts = vec![from];
    let mut found = None;
    scan_cuts(text, from, false, |i| {
        if i >= after {
            if let Some(k) = resync(i) {
                found = Some(k);
                return ControlFlow::Break(());
            }
        }
        starts.push(i);
        ControlFlow::Continue(())
    })?;
    Some((starts, found))
}

/// Walks `text` from `from` (a cut) and calls `cut` with every later cut: a line start outside
/// any block, string and comment whose first character (after its indentation when `indented`)
/// is a letter; stops when `cut` breaks. `None` when the braces, strings or comments of the text
/// do not allow a safe cut (a scan stopped by `cut` has not looked further).
fn scan_cuts(
    text: &str,
    from: usize,
    indented: bool,
    mut cut: impl FnMut(usize) -> ControlFlow<()>,
) -> Option<()> {
    let bytes = text.as_bytes();
    let mut depth: i64 = 0;
    let mut i = from;
    let mut line_start = true;
    while i < bytes.len() {
        let b = bytes[i];
        if line_start && depth == 0 && i > from {
            let first = if indented {
                bytes[i..].iter().find(|c| !matches!(c, b' ' | b'\t')).copied()
            } else {
                Some(b)
            };
            if first.is_some_and(|c| c.is_ascii_alphabetic()) && cut(i).is_break() {
                return Some(());
            }
        }
        line_start = false;
        match b {
            b'\n' => line_start = true,
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth < 0 {
                    return None;
                }
            }
            b'"' | b'/' => match literal_at(text, i) {
                Literal::EndsAt(end) => i = end,
                Literal::Uncuttable => return None,
                Literal::Neither => {}
            },
            _ => {}
        }
        i += 1;
    }
    (depth == 0).then_some(())
}

/// What starts at a byte, for the scanners that cut the text.
enum Literal {
    /// Neither a string nor a comment.
    Neither,
    /// A string or comment ending at this byte.
    EndsAt(usize),
    /// One no safe cut can be made around: a string that runs to the end of its line, a block
    /// comment left open or over several lines (which could hide a line start).
    Uncuttable,
}

/// Whether a string or a comment starts at byte `i`, and where it ends.
fn literal_at(text: &str, i: usize) -> Literal {
    let bytes = text.as_bytes();
    match (bytes.get(i), bytes.get(i + 1)) {
        (Some(b'"'), _) => {
            let mut j = i + 1;
            loop {
                match bytes.get(j) {
                    None | Some(b'\n' | b'\r') => return Literal::Uncuttable,
                    Some(b'\\') => j += 2,
                    Some(b'"') => return Literal::EndsAt(j),
                    Some(_) => j += 1,
                }
            }
        }
        (Some(b'/'), Some(b'/')) => {
            Literal::EndsAt(text[i..].find('\n').map_or(text.len(), |n| i + n) - 1)
        }
        (Some(b'/'), Some(b'*')) => text
            .get(i + 2..)
            .and_then(|rest| rest.find("*/"))
            .filter(|&close| !text[i..i + 2 + close].contains('\n'))
            .map_or(Literal::Uncuttable, |close| Literal::EndsAt(i + 2 + close + 1)),
        _ => Literal::Neither,
    }
}

/// Parses the whole text at once, with no cache: what [`parse_cached`] falls back to, and the
/// reference the tests hold it to.
///
/// A block left open makes pest fail at the end of the file. Each such block is reported
/// (E0101 at its `{`, with where its `}` belongs) and the text is read again with a `}` where the
/// block ended, so that the blocks after it are still read and their problems reported; the
/// tree's spans are those of the file (the inserted `}` is empty, at the end of the block).
pub fn parse_whole(sources: &SourceMap, file: FileId) -> Outcome<ast::File> {
    if let Some(too_deep) = too_deep(sources, file) {
        return too_deep;
    }
    let original = &sources.get(file).text;
    let whole = Span::new(file, 0, original.len());
    // The text read, and what was inserted into it: (offset in the text read, length).
    let mut text = original.to_string();
    let mut inserted: Vec<(usize, usize)> = Vec::new();
    let mut unclosed = Vec::new();
    // Every round closes one more block, so there are at most as many rounds as `{`.
    let rounds = original.bytes().filter(|b| *b == b'{').count() + 1;
    for _ in 0..rounds {
        let error = match HoloParser::parse(Rule::file, &text) {
            Ok(mut pairs) => {
                let file_pair = pairs.next().expect("the file rule always yields one pair");
                let mut builder = Builder { file, text: &text, diagnostics: Vec::new() };
                let mut ast = builder.file(file_pair);
                let mut diagnostics = builder.diagnostics;
                let m = relocate::Move { file, delta: 0, inserted: &inserted };
                relocate::Relocate::relocate(&mut ast.items, m);
                relocate::Relocate::relocate(&mut diagnostics, m);
                ast.span = whole;
                unclosed.extend(diagnostics);
                // Source order: the recovery's diagnostics among the others.
                unclosed.sort_by_key(|d| d.primary.as_ref().map_or(0, |p| p.span.start));
                return Outcome::new(ast, unclosed);
            }
            Err(error) => error,
        };
        let Some(found) = errors::unclosed_brace(file, &text) else {
            let mut diagnostic = errors::from_pest(file, 0, &error, Context::Top, &text);
            relocate::Relocate::relocate(
                &mut diagnostic,
                relocate::Move { file, delta: 0, inserted: &inserted },
            );
            unclosed.push(diagnostic);
            break;
        };
        let mut diagnostic = found.diagnostic;
        relocate::Relocate::relocate(
            &mut diagnostic,
            relocate::Move { file, delta: 0, inserted: &inserted },
        );
        // A `}` that did not close the block (it fell in a comment): no second report.
        if unclosed.iter().any(|d: &Diagnostic| d.primary == diagnostic.primary) {
            break;
        }
        unclosed.push(diagnostic);
        text.insert_str(found.insert_at, &found.insert);
        for (pos, _) in &mut inserted {
            if *pos >= found.insert_at {
                *pos += found.insert.len();
            }
        }
        inserted.push((found.insert_at, found.insert.len()));
        inserted.sort_unstable();
    }
    let ast = ast::File {
        items: vec![ast::Item::Error(ast::ErrorNode { text: original.to_string(), span: whole })],
        span: whole,
    };
    Outcome::new(ast, unclosed)
}

/// The deepest nesting of braces the parser reads. The grammar is recursive in its blocks
/// (`instance` and `on top` blocks hold statements that open blocks, a bad line's braces are
/// matched), and so are the AST's walkers; a scene needs four levels, and this bound keeps
/// every recursion over a file within a small stack (a 2 MiB thread reads it).
pub const MAX_NESTING: usize = 64;

/// The byte offset of the first `{` nested deeper than [`MAX_NESTING`], outside strings and
/// comments (a string ends at its line's end, as the grammar reads it). One pass, no recursion.
pub(crate) fn first_too_deep(text: &str) -> Option<usize> {
    first_too_deep_from(text, 0)
}

/// [`first_too_deep`] for a text that starts `depth` blocks deep.
fn first_too_deep_from(text: &str, depth: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = depth;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Some(i);
                }
            }
            b'}' => depth = depth.saturating_sub(1),
            b'"' => {
                i += 1;
                while i < bytes.len() && !matches!(bytes[i], b'"' | b'\n' | b'\r') {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(bytes.len(), |close| i + 2 + close + 1);
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// For a text nested deeper than [`MAX_NESTING`] or holding more than [`MAX_TOKENS`] tokens:
/// the whole text as one unreadable item and E0107 at the first brace too deep (or E0010 at
/// the first token too many). The grammar is never run on such a text.
fn too_deep(sources: &SourceMap, file: FileId) -> Option<Outcome<ast::File>> {
    let text = &sources.get(file).text;
    let whole = Span::new(file, 0, text.len());
    let d = if let Some(at) = first_too_deep(text) {
        Diagnostic::new(
            Code::E0107,
            format!(
                "blocks are nested deeper than {MAX_NESTING} levels; the file is not read further"
            ),
        )
        .with_primary(Span::new(file, at, at + 1), format!("level {}", MAX_NESTING + 1))
        .with_help("remove the extra braces: a scene's blocks close within four levels")
    } else {
        let at = first_token_past_limit(text)?;
        let end = text[at..].chars().next().map_or(at, |c| at + c.len_utf8());
        Diagnostic::new(
            Code::E0010,
            format!("the file holds more than {MAX_TOKENS} tokens; it is not read further"),
        )
        .with_primary(Span::new(file, at, end), format!("token {}", MAX_TOKENS + 1))
        .with_help(
            "a house of a hundred rooms holds a twentieth of that: split the file, or remove what is repeated by mistake",
        )
    };
    let ast = ast::File {
        items: vec![ast::Item::Error(ast::ErrorNode { text: text.to_string(), span: whole })],
        span: whole,
    };
    Some(Outcome::new(ast, vec![d]))
}

/// The most tokens a file may hold: words and numbers (each run of letters, digits, `_`, `-`
/// and `.`), strings, and every other character that is not blank, outside comments. The
/// classroom example holds 500; a house of a hundred such rooms, 50,000. Past this a file is
/// refused before it is parsed (E0010), so that its tree, scene and plan stay within a bounded
/// size whatever the file repeats: 32 MiB of small rooms, objects, doors, windows or corners
/// is 5 to 10 million tokens, several GB once parsed, checked and planned.
pub const MAX_TOKENS: usize = 1_000_000;

/// Where the token past [`MAX_TOKENS`] begins, if the text has one.
pub(crate) fn first_token_past_limit(text: &str) -> Option<usize> {
    scan_tokens(text, MAX_TOKENS).1
}

/// How many tokens the text holds, as [`MAX_TOKENS`] counts them.
pub fn count_tokens(text: &str) -> usize {
    scan_tokens(text, usize::MAX).0
}

/// The tokens of `text` up to `limit`, and where the one past it begins.
fn scan_tokens(text: &str, limit: usize) -> (usize, Option<usize>) {
    let bytes = text.as_bytes();
    let word = |b: u8| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.') || b >= 0x80;
    let mut count = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        match bytes[i] {
            b' ' | b'\t' | b'\n' | b'\r' => {
                i += 1;
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = text[i..].find('\n').map_or(bytes.len(), |end| i + end);
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(bytes.len(), |close| i + 2 + close + 2);
                continue;
            }
            b'"' => {
                i += 1;
                while i < bytes.len() && !matches!(bytes[i], b'"' | b'\n' | b'\r') {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            b if word(b) => {
                while i < bytes.len() && word(bytes[i]) {
                    i += 1;
                }
            }
            _ => i += 1,
        }
        count += 1;
        if count > limit {
            return (count - 1, Some(start));
        }
    }
    (count, None)
}

/// Parses a text that is not in a source map (tests, the importer's round-trip check).
pub fn parse_str(text: &str) -> Outcome<ast::File> {
    let mut sources = SourceMap::new();
    let id = sources.add("<text>", text);
    parse(&sources, id)
}

struct Builder<'a> {
    file: FileId,
    text: &'a str,
    diagnostics: Vec<Diagnostic>,
}

impl Builder<'_> {
    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        let s = pair.as_span();
        Span::new(self.file, s.start(), s.end())
    }

    fn file(&mut self, pair: Pair<'_, Rule>) -> ast::File {
        let span = self.span(&pair);
        let mut items = Vec::new();
        let mut previous_end: Option<usize> = None;
        for p in children(pair) {
            if p.as_rule() == Rule::EOI {
                continue;
            }
            let start = p.as_span().start();
            if self.blank_between(previous_end, start) {
                items.push(ast::Item::Blank(Span::new(self.file, start, start)));
            }
            previous_end = Some(p.as_span().end());
            match p.as_rule() {
                Rule::scene => items.push(ast::Item::Scene(self.scene(p))),
                Rule::room => items.push(ast::Item::Room(self.room(p))),
                Rule::door => items.push(ast::Item::Door(self.door(p))),
                Rule::comment | Rule::trailing_comment => {
                    items.push(ast::Item::Comment(self.comment(p)));
                }
                Rule::bad_line => items.push(ast::Item::Error(self.bad_line(p, Context::Top))),
                Rule::stray_brace => {
                    let span = self.span(&p);
                    self.diagnostics.push(
                        Diagnostic::new(Code::E0101, "unmatched `}`")
                            .with_primary(span, "this closes no block")
                            .with_help("remove it, or add the `{` it was meant to close"),
                    );
                    items.push(ast::Item::Error(ast::ErrorNode { text: "}".into(), span }));
                }
                _ => {}
            }
        }
        ast::File { items, span }
    }

    /// Whether an empty line separates the previous item (ending at `previous_end`) from an
    /// item starting at `start`.
    fn blank_between(&self, previous_end: Option<usize>, start: usize) -> bool {
        let Some(end) = previous_end else { return false };
        self.text.get(end..start).is_some_and(|gap| gap.matches('\n').count() >= 2)
    }

    fn comment(&self, pair: Pair<'_, Rule>) -> ast::Comment {
        let trailing = pair.as_rule() == Rule::trailing_comment;
        let span = self.span(&pair);
        ast::Comment { text: pair.as_str().trim_end().to_string(), trailing, span }
    }

    fn bad_line(&mut self, pair: Pair<'_, Rule>, context: Context) -> ast::ErrorNode {
        let span = self.span(&pair);
        let line = pair.as_str();
        self.diagnostics.push(errors::bad_line(self.file, span.start as usize, line, context));
        ast::ErrorNode { text: line.trim_end().to_string(), span }
    }

    fn ident(&self, pair: Pair<'_, Rule>) -> Ident {
        Ident::new(pair.as_str(), self.span(&pair))
    }

    fn string(&mut self, pair: Pair<'_, Rule>) -> Str {
        let span = self.span(&pair);
        let inner = children(pair).next().map_or("", |p| p.as_str());
        Str { value: unescape(inner), span }
    }

    fn quantity(&mut self, pair: Pair<'_, Rule>) -> Quantity {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let number = inner.next().expect("a quantity starts with a number");
        let text = number.as_str().to_string();
        let value = text.parse::<f64>().unwrap_or(f64::NAN);
        if !value.is_finite() {
            self.diagnostics.push(
                Diagnostic::new(Code::E0103, format!("the number `{text}` is too large"))
                    .with_primary(self.span(&number), "not a finite number")
                    .with_help("write a number of at most 15 digits"),
            );
        }
        let (unit, unit_span) = match inner.next() {
            Some(u) => (Some(unit_of(u.as_str())), Some(self.span(&u))),
            None => (None, None),
        };
        Quantity { value: if value.is_finite() { value } else { 0.0 }, text, unit, unit_span, span }
    }

    fn body_items<T>(
        &mut self,
        pair: Pair<'_, Rule>,
        context: Context,
        mut stmt: impl FnMut(&mut Self, Pair<'_, Rule>) -> Option<T>,
        comment: impl Fn(ast::Comment) -> T,
        error: impl Fn(ast::ErrorNode) -> T,
        blank: impl Fn(Span) -> T,
    ) -> Vec<T> {
        let mut out = Vec::new();
        let mut previous_end: Option<usize> = None;
        for p in children(pair) {
            let start = p.as_span().start();
            if self.blank_between(previous_end, start) {
                out.push(blank(Span::new(self.file, start, start)));
            }
            previous_end = Some(p.as_span().end());
            match p.as_rule() {
                Rule::comment | Rule::trailing_comment => out.push(comment(self.comment(p))),
                Rule::bad_line => {
                    let node = self.bad_line(p, context);
                    out.push(error(node));
                }
                _ => {
                    if let Some(item) = stmt(self, p) {
                        out.push(item);
                    }
                }
            }
        }
        out
    }

    fn scene(&mut self, pair: Pair<'_, Rule>) -> ast::SceneBlock {
        let span = self.span(&pair);
        let mut request = None;
        let mut body = Vec::new();
        for p in children(pair) {
            match p.as_rule() {
                Rule::string => request = Some(self.string(p)),
                Rule::scene_body => {
                    body = self.body_items(
                        p,
                        Context::Scene,
                        |b, s| {
                            let span = b.span(&s);
                            let rule = s.as_rule();
                            let value = children(s)
                                .find(|c| matches!(c.as_rule(), Rule::quantity | Rule::string))?;
                            match (rule, value.as_rule()) {
                                (Rule::wall_height, Rule::quantity) => {
                                    Some(ast::SceneStmt::WallHeight(b.quantity(value), span))
                                }
                                (Rule::seed, Rule::quantity) => {
                                    Some(ast::SceneStmt::Seed(b.quantity(value), span))
                                }
                                (Rule::ceiling_material, Rule::string) => {
                                    Some(ast::SceneStmt::CeilingMaterial(b.string(value), span))
                                }
                                (Rule::ceiling_design, Rule::string) => {
                                    Some(ast::SceneStmt::CeilingDesign(b.string(value), span))
                                }
                                _ => None,
                            }
                        },
                        ast::SceneStmt::Comment,
                        ast::SceneStmt::Error,
                        ast::SceneStmt::Blank,
                    );
                }
                _ => {}
            }
        }
        ast::SceneBlock { request, body, span }
    }

    fn room(&mut self, pair: Pair<'_, Rule>) -> ast::Room {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let id = self.ident(inner.next().expect("a room has an identifier"));
        let mut label = None;
        let mut body = Vec::new();
        for p in inner {
            match p.as_rule() {
                Rule::string => label = Some(self.string(p)),
                Rule::room_body => {
                    body = self.body_items(
                        p,
                        Context::Room,
                        Builder::room_stmt,
                        ast::RoomStmt::Comment,
                        ast::RoomStmt::Error,
                        ast::RoomStmt::Blank,
                    );
                }
                _ => {}
            }
        }
        ast::Room { id, label, body, span }
    }

    fn room_stmt(&mut self, pair: Pair<'_, Rule>) -> Option<ast::RoomStmt> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        Some(match rule {
            Rule::floor_design | Rule::wall_design | Rule::floor_material | Rule::wall_material => {
                let s = self.string(children(pair).next()?);
                match rule {
                    Rule::floor_design => ast::RoomStmt::FloorDesign(s, span),
                    Rule::wall_design => ast::RoomStmt::WallDesign(s, span),
                    Rule::floor_material => ast::RoomStmt::FloorMaterial(s, span),
                    _ => ast::RoomStmt::WallMaterial(s, span),
                }
            }
            Rule::corners => {
                let mut unit = None;
                let mut points = Vec::new();
                for p in children(pair) {
                    match p.as_rule() {
                        Rule::corners_unit => {
                            let u = children(p).next()?;
                            unit = Some((unit_of(u.as_str()), self.span(&u)));
                        }
                        Rule::point => {
                            let pspan = self.span(&p);
                            let mut q = children(p);
                            let x = self.quantity(q.next()?);
                            let z = self.quantity(q.next()?);
                            points.push(ast::Point { x, z, span: pspan });
                        }
                        _ => {}
                    }
                }
                ast::RoomStmt::Corners(ast::Corners { unit, points, span })
            }
            Rule::window => ast::RoomStmt::Window(Box::new(self.window(pair)?)),
            Rule::object => ast::RoomStmt::Object(self.object(pair)?),
            Rule::wall_object => ast::RoomStmt::WallObject(self.object(pair)?),
            Rule::ceiling => {
                let mut inner = children(pair);
                let description = self.string(inner.next()?);
                let body = match inner.next() {
                    Some(block) => self.object_block(block),
                    None => Vec::new(),
                };
                ast::RoomStmt::Ceiling(ast::Ceiling { description, body, span })
            }
            _ => return None,
        })
    }

    fn window(&mut self, pair: Pair<'_, Rule>) -> Option<ast::Window> {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let wall = self.ident(inner.next()?);
        let kind = self.ident(inner.next()?);
        let width = self.quantity(inner.next()?);
        let height = self.quantity(inner.next()?);
        let mut window =
            ast::Window { wall, kind, width, height, count: None, sill: None, asset: None, span };
        for opt in inner {
            let rule = opt.as_rule();
            let value = children(opt).next()?;
            match rule {
                Rule::window_count => window.count = Some(self.quantity(value)),
                Rule::window_sill => window.sill = Some(self.quantity(value)),
                Rule::window_asset => window.asset = Some(self.string(value)),
                _ => {}
            }
        }
        Some(window)
    }

    fn object(&mut self, pair: Pair<'_, Rule>) -> Option<ast::Object> {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let id = self.ident(inner.next()?);
        let category = self.string(inner.next()?);
        let (body, has_block) = match inner.next() {
            Some(block) => (self.object_block(block), true),
            None => (Vec::new(), false),
        };
        Some(ast::Object { id, category, body, has_block, span })
    }

    fn object_block(&mut self, pair: Pair<'_, Rule>) -> Vec<ast::ObjectStmt> {
        let Some(body) = children(pair).next() else { return Vec::new() };
        self.body_items(
            body,
            Context::Object,
            Builder::object_stmt,
            ast::ObjectStmt::Comment,
            ast::ObjectStmt::Error,
            ast::ObjectStmt::Blank,
        )
    }

    fn object_stmt(&mut self, pair: Pair<'_, Rule>) -> Option<ast::ObjectStmt> {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = children(pair);
        Some(match rule {
            Rule::describe => ast::ObjectStmt::Describe(self.string(inner.next()?), span),
            Rule::asset => ast::ObjectStmt::Asset(self.string(inner.next()?), span),
            Rule::size => {
                let width = self.quantity(inner.next()?);
                let depth = self.quantity(inner.next()?);
                let height = self.quantity(inner.next()?);
                ast::ObjectStmt::Size(ast::Size3 { width, depth, height, span })
            }
            Rule::count => {
                let n = self.quantity(inner.next()?);
                let variance = inner.next().map(|w| self.ident(w));
                ast::ObjectStmt::Count(n, variance, span)
            }
            Rule::above => ast::ObjectStmt::Above(self.ident(inner.next()?), span),
            Rule::height => ast::ObjectStmt::Height(self.quantity(inner.next()?), span),
            Rule::at => ast::ObjectStmt::At(inner.map(|q| self.quantity(q)).collect(), span),
            Rule::facing => ast::ObjectStmt::Facing(self.quantity(inner.next()?), span),
            Rule::constraint => {
                let relation = inner.next()?;
                let words: Vec<&str> = relation.as_str().split_whitespace().collect();
                let name = Ident::new(words.join(" "), self.span(&relation));
                let target = inner.next().map(|t| self.ident(t));
                ast::ObjectStmt::Constraint(ast::Constraint { name, target, span })
            }
            Rule::on_top => {
                let item = self.string(inner.next()?);
                let mut on_top =
                    ast::OnTop { item, count: None, variance: None, body: Vec::new(), span };
                for p in inner {
                    match p.as_rule() {
                        Rule::on_top_count => {
                            let q = children(p).next()?;
                            let qspan = self.span(&q);
                            let text = q.as_str().to_string();
                            let value = text.parse::<f64>().unwrap_or(0.0);
                            on_top.count = Some(Quantity {
                                value,
                                text,
                                unit: None,
                                unit_span: None,
                                span: qspan,
                            });
                        }
                        Rule::word => on_top.variance = Some(self.ident(p)),
                        Rule::object_block => on_top.body = self.object_block(p),
                        _ => {}
                    }
                }
                ast::ObjectStmt::OnTop(on_top)
            }
            Rule::instance => {
                let id = self.ident(inner.next()?);
                let body = self.object_block(inner.next()?);
                ast::ObjectStmt::Instance(ast::Instance { id, body, span })
            }
            _ => return None,
        })
    }

    fn door(&mut self, pair: Pair<'_, Rule>) -> ast::Door {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let from = self.ident(inner.next().expect("a door has a first side"));
        let to = self.ident(inner.next().expect("a door has a second side"));
        let kind = self.ident(inner.next().expect("a door has a kind"));
        let mut door = ast::Door { from, to, kind, size: None, style: None, asset: None, span };
        for p in inner {
            match p.as_rule() {
                Rule::door_size => door.size = children(p).next().map(|w| self.ident(w)),
                Rule::string => door.style = Some(self.string(p)),
                Rule::door_asset => {
                    if let Some(s) = children(p).next() {
                        door.asset = Some(self.string(s));
                    }
                }
                _ => {}
            }
        }
        door
    }
}

/// The children of a pair, without the keyword tokens.
fn children(pair: Pair<'_, Rule>) -> impl Iterator<Item = Pair<'_, Rule>> {
    pair.into_inner().filter(|p| !is_keyword(p.as_rule()))
}

fn is_keyword(rule: Rule) -> bool {
    matches!(
        rule,
        Rule::kw_scene
            | Rule::kw_room
            | Rule::kw_door
            | Rule::kw_wall
            | Rule::kw_walls
            | Rule::kw_height
            | Rule::kw_seed
            | Rule::kw_floor
            | Rule::kw_material
            | Rule::kw_corners
            | Rule::kw_in
            | Rule::kw_window
            | Rule::kw_count
            | Rule::kw_sill
            | Rule::kw_asset
            | Rule::kw_object
            | Rule::kw_ceiling
            | Rule::kw_describe
            | Rule::kw_size
            | Rule::kw_above
            | Rule::kw_at
            | Rule::kw_facing
            | Rule::kw_on
            | Rule::kw_top
            | Rule::kw_instance
    )
}

fn unit_of(text: &str) -> Unit {
    match text {
        "m" => Unit::M,
        "cm" => Unit::Cm,
        "deg" => Unit::Deg,
        "mm" => Unit::Mm,
        "ft" => Unit::Ft,
        "in" => Unit::In,
        _ => Unit::Rad,
    }
}

/// Resolves the escapes of a string's inside (the grammar guarantees they are well formed).
fn unescape(inner: &str) -> String {
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('u') => {
                let hex: String = chars.by_ref().skip(1).take_while(|c| *c != '}').collect();
                out.push(
                    u32::from_str_radix(&hex, 16)
                        .ok()
                        .and_then(char::from_u32)
                        .unwrap_or(char::REPLACEMENT_CHARACTER),
                );
            }
            Some(other) => out.push(other),
            None => {}
        }
    }
    out
}

/// Escapes a string value for printing between double quotes.
pub fn escape(value: &str) -> String {
    let mut out = String::with_capacity(value.len());
    for c in value.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\u{d}"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    out
}
