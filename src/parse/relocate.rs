//! Moving a parsed piece of text: every span of a syntax subtree (or a diagnostic) shifted by a
//! byte delta and given a file id. The chunked parser parses a top-level item once and reuses
//! it wherever the same text appears again (an editor's next keystroke, elsewhere in the file).

use crate::ast::{
    Ceiling, Comment, Constraint, Corners, Door, ErrorNode, Ident, Instance, Item, Object,
    ObjectStmt, OnTop, Point, Quantity, Room, RoomStmt, SceneBlock, SceneStmt, Size3, Str, Window,
};
use crate::diag::Diagnostic;
use crate::source::{FileId, Span};

/// A relocation: the file the spans now belong to and how far they move.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Move<'a> {
    pub file: FileId,
    pub delta: i64,
    /// Text the parser read that the file does not hold (the `}` recovery inserts for a block
    /// left open), as (offset in the text read, length), in order: offsets after an insertion
    /// move back by its length, offsets inside one move to where it was inserted.
    pub inserted: &'a [(usize, usize)],
}

impl Move<'_> {
    /// A plain shift by `delta` into `file`.
    pub(crate) fn shift(file: FileId, delta: i64) -> Move<'static> {
        Move { file, delta, inserted: &[] }
    }

    /// Where the offset `at` of the text read lies in the file.
    fn offset(&self, at: u32) -> u32 {
        let at = at as usize;
        let mut removed = 0usize;
        for &(pos, len) in self.inserted {
            if pos >= at {
                break;
            }
            removed += (at - pos).min(len);
        }
        (((at - removed) as i64) + self.delta).max(0) as u32
    }
}

/// Something with spans to move.
pub(crate) trait Relocate {
    fn relocate(&mut self, m: Move);
}

impl Relocate for Span {
    fn relocate(&mut self, m: Move) {
        self.file = m.file;
        self.start = m.offset(self.start);
        self.end = m.offset(self.end);
    }
}

impl<T: Relocate> Relocate for Option<T> {
    fn relocate(&mut self, m: Move) {
        if let Some(x) = self {
            x.relocate(m);
        }
    }
}

impl<T: Relocate> Relocate for Box<T> {
    fn relocate(&mut self, m: Move) {
        T::relocate(self, m);
    }
}

impl<T: Relocate> Relocate for Vec<T> {
    fn relocate(&mut self, m: Move) {
        for x in self {
            x.relocate(m);
        }
    }
}

impl<A: Relocate, B: Relocate> Relocate for (A, B) {
    fn relocate(&mut self, m: Move) {
        self.0.relocate(m);
        self.1.relocate(m);
    }
}

impl Relocate for crate::ast::Unit {
    fn relocate(&mut self, _: Move) {}
}

macro_rules! spans {
    ($($ty:ty => $($field:ident),*;)*) => {
        $(impl Relocate for $ty {
            fn relocate(&mut self, m: Move) {
                $(self.$field.relocate(m);)*
            }
        })*
    };
}

spans! {
    Ident => span;
    Str => span;
    Quantity => unit_span, span;
    Comment => span;
    ErrorNode => span;
    SceneBlock => request, body, span;
    Room => id, label, body, span;
    Corners => unit, points, span;
    Point => x, z, span;
    Window => wall, kind, width, height, count, sill, asset, span;
    Object => id, category, body, span;
    Size3 => width, depth, height, span;
    Constraint => name, target, span;
    Instance => id, body, span;
    OnTop => item, count, variance, body, span;
    Ceiling => description, body, span;
    Door => from, to, kind, size, style, asset, span;
}

impl Relocate for Item {
    fn relocate(&mut self, m: Move) {
        match self {
            Item::Scene(x) => x.relocate(m),
            Item::Room(x) => x.relocate(m),
            Item::Door(x) => x.relocate(m),
            Item::Comment(x) => x.relocate(m),
            Item::Blank(x) => x.relocate(m),
            Item::Error(x) => x.relocate(m),
        }
    }
}

impl Relocate for SceneStmt {
    fn relocate(&mut self, m: Move) {
        match self {
            SceneStmt::WallHeight(q, s) | SceneStmt::Seed(q, s) => {
                q.relocate(m);
                s.relocate(m);
            }
            SceneStmt::CeilingMaterial(x, s) | SceneStmt::CeilingDesign(x, s) => {
                x.relocate(m);
                s.relocate(m);
            }
            SceneStmt::Comment(c) => c.relocate(m),
            SceneStmt::Blank(s) => s.relocate(m),
            SceneStmt::Error(e) => e.relocate(m),
        }
    }
}

impl Relocate for RoomStmt {
    fn relocate(&mut self, m: Move) {
        match self {
            RoomStmt::FloorDesign(x, s)
            | RoomStmt::WallDesign(x, s)
            | RoomStmt::FloorMaterial(x, s)
            | RoomStmt::WallMaterial(x, s) => {
                x.relocate(m);
                s.relocate(m);
            }
            RoomStmt::Corners(c) => c.relocate(m),
            RoomStmt::Window(w) => w.relocate(m),
            RoomStmt::Object(o) | RoomStmt::WallObject(o) => o.relocate(m),
            RoomStmt::Ceiling(c) => c.relocate(m),
            RoomStmt::Comment(c) => c.relocate(m),
            RoomStmt::Blank(s) => s.relocate(m),
            RoomStmt::Error(e) => e.relocate(m),
        }
    }
}

impl Relocate for ObjectStmt {
    fn relocate(&mut self, m: Move) {
        match self {
            ObjectStmt::Describe(x, s) | ObjectStmt::Asset(x, s) => {
                x.relocate(m);
                s.relocate(m);
            }
            ObjectStmt::Size(x) => x.relocate(m),
            ObjectStmt::Count(q, w, s) => {
                q.relocate(m);
                w.relocate(m);
                s.relocate(m);
            }
            ObjectStmt::Constraint(c) => c.relocate(m),
            ObjectStmt::Above(i, s) => {
                i.relocate(m);
                s.relocate(m);
            }
            ObjectStmt::Height(q, s) | ObjectStmt::Facing(q, s) => {
                q.relocate(m);
                s.relocate(m);
            }
            ObjectStmt::At(qs, s) => {
                qs.relocate(m);
                s.relocate(m);
            }
            ObjectStmt::OnTop(t) => t.relocate(m),
            ObjectStmt::Instance(i) => i.relocate(m),
            ObjectStmt::Comment(c) => c.relocate(m),
            ObjectStmt::Blank(s) => s.relocate(m),
            ObjectStmt::Error(e) => e.relocate(m),
        }
    }
}

impl Relocate for Diagnostic {
    fn relocate(&mut self, m: Move) {
        if let Some(p) = &mut self.primary {
            p.span.relocate(m);
        }
        for l in &mut self.secondary {
            l.span.relocate(m);
        }
        for f in &mut self.fixes {
            f.span.relocate(m);
        }
    }
}
