//! Where every room and object of a `.holo` file is declared and named: what go to definition,
//! find references, rename, hover and document symbols read.
//!
//! The index is built from the syntax tree alone, so it is there even when the file has errors
//! further on. Object names are scoped to their room, as the checker scopes them; a name such as
//! `chair-1` is an instance of the group `chair` when no group is called `chair-1`.

use crate::ast::{self, Ident, ObjectStmt, RoomStmt};
use crate::source::Span;

/// What a symbol is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SymbolKind {
    /// A room.
    Room,
    /// A floor object group.
    Object,
    /// A wall object group.
    WallObject,
}

/// A declared room or object group.
#[derive(Clone, Debug, PartialEq)]
pub struct Symbol {
    /// Room or object.
    pub kind: SymbolKind,
    /// The identifier.
    pub name: String,
    /// The room label or the object's category.
    pub detail: Option<String>,
    /// For objects: the index of the room symbol they belong to.
    pub room: Option<usize>,
    /// The identifier where it is declared.
    pub name_span: Span,
    /// The whole declaration.
    pub decl_span: Span,
    /// For object groups: `instance NAME { ... }` blocks, as (index, identifier span, block span).
    pub instance_blocks: Vec<(u32, Span, Span)>,
    /// For object groups: how many instances the group declares (as the checker counts them,
    /// read from the syntax tree so that it is known while a line is half typed); 1 for rooms.
    pub count: u32,
}

/// One place a symbol is named.
#[derive(Clone, Debug, PartialEq)]
pub struct Occurrence {
    /// Index in [`Index::symbols`].
    pub symbol: usize,
    /// The whole name as written (`chair-1`).
    pub span: Span,
    /// The part that is the symbol's own name (`chair` of `chair-1`): what a rename replaces.
    pub name_span: Span,
    /// The instance named, when the name is `<group>-<n>`.
    pub instance: Option<u32>,
    /// Whether this is the declaration.
    pub is_declaration: bool,
}

/// A relation written in an object block.
#[derive(Clone, Debug, PartialEq)]
pub struct RelationSite {
    /// The relation's words as written (`in front of`).
    pub words: String,
    /// Where the words are.
    pub words_span: Span,
    /// The whole constraint.
    pub span: Span,
}

/// Every symbol and occurrence of one file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Index {
    /// Rooms and object groups in declaration order.
    pub symbols: Vec<Symbol>,
    /// Every place a symbol is named, declarations included, in text order per kind.
    pub occurrences: Vec<Occurrence>,
    /// Every relation and global constraint written.
    pub relations: Vec<RelationSite>,
    /// Object groups by (room symbol, name): the first declared wins, as in the checker.
    objects_by_name: std::collections::HashMap<(usize, String), usize>,
    /// Room symbols by name: the first declared wins.
    rooms_by_name: std::collections::HashMap<String, usize>,
}

impl Index {
    /// Indexes a syntax tree.
    pub fn new(file: &ast::File) -> Index {
        let mut index = Index::default();
        // Rooms first, so that doors anywhere in the file find them.
        for item in &file.items {
            if let ast::Item::Room(room) = item {
                let r = index.symbols.len();
                index.symbols.push(Symbol {
                    kind: SymbolKind::Room,
                    name: room.id.name.clone(),
                    detail: room.label.as_ref().map(|l| l.value.clone()),
                    room: None,
                    name_span: room.id.span,
                    decl_span: room.span,
                    instance_blocks: Vec::new(),
                    count: 1,
                });
                index.declare(r, room.id.span);
                index.rooms_by_name.entry(room.id.name.clone()).or_insert(r);
            }
        }
        // Rooms are the first symbols, in file order.
        let mut room_index = 0;
        for item in &file.items {
            match item {
                ast::Item::Room(room) => {
                    index.room_body(room_index, room);
                    room_index += 1;
                }
                ast::Item::Door(door) => {
                    for side in [&door.from, &door.to] {
                        if let Some(r) = index.room_named(&side.name) {
                            index.occurrences.push(Occurrence {
                                symbol: r,
                                span: side.span,
                                name_span: side.span,
                                instance: None,
                                is_declaration: false,
                            });
                        }
                    }
                }
                _ => {}
            }
        }
        index
    }

    fn declare(&mut self, symbol: usize, span: Span) {
        self.occurrences.push(Occurrence {
            symbol,
            span,
            name_span: span,
            instance: None,
            is_declaration: true,
        });
    }

    /// The room symbol with this identifier (the first, if declared twice).
    pub fn room_named(&self, name: &str) -> Option<usize> {
        self.rooms_by_name.get(name).copied()
    }

    /// The object groups of a room symbol.
    pub fn objects_of(&self, room: usize) -> impl Iterator<Item = (usize, &Symbol)> {
        self.symbols.iter().enumerate().filter(move |(_, s)| s.room == Some(room))
    }

    fn room_body(&mut self, r: usize, room: &ast::Room) {
        // Declarations first: a constraint may name an object declared further down.
        let mut declared = Vec::new();
        for stmt in &room.body {
            let (object, kind) = match stmt {
                RoomStmt::Object(o) => (o, SymbolKind::Object),
                RoomStmt::WallObject(o) => (o, SymbolKind::WallObject),
                _ => continue,
            };
            let s = self.symbols.len();
            let mut instance_blocks = Vec::new();
            for inner in &object.body {
                if let ObjectStmt::Instance(inst) = inner {
                    if let Some(n) = instance_number(&inst.id.name, &object.id.name) {
                        instance_blocks.push((n, inst.id.span, inst.span));
                    }
                }
            }
            self.symbols.push(Symbol {
                kind,
                name: object.id.name.clone(),
                detail: Some(object.category.value.clone()),
                room: Some(r),
                name_span: object.id.span,
                decl_span: object.span,
                instance_blocks,
                count: crate::check::declared_count(object),
            });
            self.declare(s, object.id.span);
            self.objects_by_name.entry((r, object.id.name.clone())).or_insert(s);
            declared.push(s);
        }
        let mut declared = declared.into_iter();
        for stmt in &room.body {
            match stmt {
                RoomStmt::Object(o) | RoomStmt::WallObject(o) => {
                    let own = declared.next();
                    self.object_body(r, own, &o.body);
                }
                RoomStmt::Ceiling(c) => self.object_body(r, None, &c.body),
                _ => {}
            }
        }
    }

    fn object_body(&mut self, r: usize, own: Option<usize>, body: &[ObjectStmt]) {
        for stmt in body {
            match stmt {
                ObjectStmt::Constraint(c) => {
                    self.relations.push(RelationSite {
                        words: c.name.name.clone(),
                        words_span: c.name.span,
                        span: c.span,
                    });
                    if let Some(target) = &c.target {
                        self.reference(r, target);
                    }
                }
                ObjectStmt::Above(target, _) => self.reference(r, target),
                ObjectStmt::Instance(inst) => {
                    if let Some(own) = own {
                        let group = self.symbols[own].name.clone();
                        if let Some(n) = instance_number(&inst.id.name, &group) {
                            self.occurrences.push(Occurrence {
                                symbol: own,
                                span: inst.id.span,
                                name_span: prefix(inst.id.span, group.len()),
                                instance: Some(n),
                                is_declaration: false,
                            });
                        }
                    }
                    self.object_body(r, own, &inst.body);
                }
                ObjectStmt::OnTop(t) => self.object_body(r, own, &t.body),
                _ => {}
            }
        }
    }

    /// Records a name that refers to an object of room `r`.
    fn reference(&mut self, r: usize, ident: &Ident) {
        if let Some(occurrence) = self.resolve_object(r, ident) {
            self.occurrences.push(occurrence);
        }
    }

    /// What an object name written in room `r` refers to.
    fn resolve_object(&self, r: usize, ident: &Ident) -> Option<Occurrence> {
        if let Some(&s) = self.objects_by_name.get(&(r, ident.name.clone())) {
            return Some(Occurrence {
                symbol: s,
                span: ident.span,
                name_span: ident.span,
                instance: None,
                is_declaration: false,
            });
        }
        let (group, _) = ident.name.rsplit_once('-')?;
        let &s = self.objects_by_name.get(&(r, group.to_string()))?;
        let n = instance_number(&ident.name, group)?;
        Some(Occurrence {
            symbol: s,
            span: ident.span,
            name_span: prefix(ident.span, group.len()),
            instance: Some(n),
            is_declaration: false,
        })
    }

    /// The occurrence whose name covers byte `offset` (its end included, as editors put the
    /// cursor just after a word).
    pub fn occurrence_at(&self, offset: usize) -> Option<&Occurrence> {
        let covers =
            |o: &&Occurrence| (o.span.start as usize) <= offset && offset <= (o.span.end as usize);
        // Prefer one that starts at or before the cursor strictly inside over an end-touch.
        self.occurrences
            .iter()
            .filter(covers)
            .min_by_key(|o| usize::from(offset == o.span.end as usize))
    }

    /// The relation whose words cover byte `offset`.
    pub fn relation_at(&self, offset: usize) -> Option<&RelationSite> {
        self.relations.iter().find(|r| {
            (r.words_span.start as usize) <= offset && offset <= (r.words_span.end as usize)
        })
    }

    /// Every occurrence of a symbol, in text order; with `instance`, only those naming that
    /// instance (and the group's declaration).
    pub fn occurrences_of(&self, symbol: usize, instance: Option<u32>) -> Vec<&Occurrence> {
        let mut found: Vec<&Occurrence> = self
            .occurrences
            .iter()
            .filter(|o| o.symbol == symbol)
            .filter(|o| instance.is_none() || o.is_declaration || o.instance == instance)
            .collect();
        found.sort_by_key(|o| o.span.start);
        found
    }

    /// The innermost room symbol whose declaration covers `offset`.
    pub fn room_at(&self, offset: usize) -> Option<usize> {
        self.symbols.iter().position(|s| {
            s.kind == SymbolKind::Room
                && (s.decl_span.start as usize) <= offset
                && offset < (s.decl_span.end as usize)
        })
    }

    /// The object group whose declaration covers `offset`.
    pub fn object_at(&self, offset: usize) -> Option<usize> {
        self.symbols.iter().position(|s| {
            s.kind != SymbolKind::Room
                && (s.decl_span.start as usize) <= offset
                && offset < (s.decl_span.end as usize)
        })
    }
}

/// `n` when `name` is `<group>-<n>`.
pub fn instance_number(name: &str, group: &str) -> Option<u32> {
    let rest = name.strip_prefix(group)?.strip_prefix('-')?;
    if rest.is_empty() || !rest.bytes().all(|b| b.is_ascii_digit()) || rest.len() > 9 {
        return None;
    }
    rest.parse().ok()
}

fn prefix(span: Span, len: usize) -> Span {
    Span::new(span.file, span.start as usize, span.start as usize + len)
}

/// Whether `name` can be written as an identifier of the language (letters, digits, `_` and
/// inner `-`, starting with a letter or `_`) and given to a room or an object group: not
/// `exterior`, and not ending in `-<number>` (which reads as an instance).
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    let Some(first) = chars.next() else { return false };
    let shape = (first.is_ascii_alphabetic() || first == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !name.ends_with('-')
        && !name.contains("--");
    let instance_like = name
        .rsplit_once('-')
        .is_some_and(|(_, n)| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
    shape && !instance_like && name != "exterior"
}
