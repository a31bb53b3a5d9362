//! The formatter: [`ast::File`] → canonical `.holo` text.
//!
//! The canonical form: two spaces of indentation per block; one statement per line; a blank
//! line around every `scene` and `room` block (a comment stays glued to the item below it);
//! doors one per line; trailing comments after their statement with one space; numbers as they
//! were written, with their unit after one space. Printing keeps every node, comments included,
//! so that parse → print → parse gives the same tree and printing twice gives the same text.
//! The importer writes `.holo` through this printer, so its output is canonical by construction.

use crate::ast::{self, Quantity};
use crate::parse::escape;
use std::fmt::Write as _;

/// Prints a file in canonical form.
pub fn print(file: &ast::File) -> String {
    let mut p = Printer { out: String::new(), indent: 0 };
    let mut previous: Option<&ast::Item> = None;
    for (index, item) in file.items.iter().enumerate() {
        if let ast::Item::Blank(_) = item {
            continue;
        }
        if let ast::Item::Comment(c) = item {
            if c.trailing && previous.is_some() {
                p.trailing(&c.text);
                continue;
            }
        }
        if let Some(prev) = previous {
            let is_block = |i: &ast::Item| matches!(i, ast::Item::Scene(_) | ast::Item::Room(_));
            let prev_is_comment = matches!(prev, ast::Item::Comment(_));
            if is_block(prev) || (is_block(item) && !prev_is_comment) {
                p.blank_line();
            }
        }
        if index > 0 && matches!(file.items[index - 1], ast::Item::Blank(_)) {
            p.blank_line();
        }
        match item {
            ast::Item::Blank(_) => {}
            ast::Item::Scene(s) => p.scene(s),
            ast::Item::Room(r) => p.room(r),
            ast::Item::Door(d) => p.door(d),
            ast::Item::Comment(c) => p.line(&c.text),
            ast::Item::Error(e) => p.line(&e.text),
        }
        previous = Some(item);
    }
    p.out
}

/// Prints a quantity: its number as written and its unit after one space.
pub fn quantity(q: &Quantity) -> String {
    match q.unit {
        Some(u) => format!("{} {}", q.text, u.as_str()),
        None => q.text.clone(),
    }
}

fn string(s: &ast::Str) -> String {
    format!("\"{}\"", escape(&s.value))
}

struct Printer {
    out: String,
    indent: usize,
}

impl Printer {
    /// Ends the current paragraph with one empty line (never two, never at the start).
    fn blank_line(&mut self) {
        if !self.out.is_empty() && !self.out.ends_with("\n\n") && !self.out.ends_with("{\n") {
            self.out.push('\n');
        }
    }

    fn line(&mut self, text: &str) {
        for _ in 0..self.indent {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// Appends a trailing comment to the last printed line.
    fn trailing(&mut self, text: &str) {
        if self.out.ends_with('\n') {
            self.out.pop();
        }
        self.out.push(' ');
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// Prints `header {`, the body, and `}`; an empty body prints `header {}`.
    fn block<T>(&mut self, header: &str, body: &[T], mut each: impl FnMut(&mut Self, &T)) {
        if body.is_empty() {
            self.line(&format!("{header} {{}}"));
            return;
        }
        self.line(&format!("{header} {{"));
        self.indent += 1;
        for stmt in body {
            each(self, stmt);
        }
        self.indent -= 1;
        self.line("}");
    }

    fn comment(&mut self, c: &ast::Comment, first: bool) {
        if c.trailing && !first {
            self.trailing(&c.text);
        } else {
            self.line(&c.text);
        }
    }

    fn scene(&mut self, s: &ast::SceneBlock) {
        let header = match &s.request {
            Some(r) => format!("scene {}", string(r)),
            None => "scene".to_string(),
        };
        let mut first = true;
        self.block(&header, &s.body, |p, stmt| {
            match stmt {
                ast::SceneStmt::WallHeight(q, _) => p.line(&format!("wall height {}", quantity(q))),
                ast::SceneStmt::Seed(q, _) => p.line(&format!("seed {}", quantity(q))),
                ast::SceneStmt::CeilingMaterial(m, _) => {
                    p.line(&format!("ceiling material {}", string(m)));
                }
                ast::SceneStmt::CeilingDesign(d, _) => p.line(&format!("ceiling {}", string(d))),
                ast::SceneStmt::Comment(c) => p.comment(c, first),
                ast::SceneStmt::Error(e) => p.line(&e.text),
                ast::SceneStmt::Blank(_) => p.blank_line(),
            }
            first = false;
        });
    }

    fn room(&mut self, r: &ast::Room) {
        let mut header = format!("room {}", r.id.name);
        if let Some(label) = &r.label {
            let _ = write!(header, " {}", string(label));
        }
        let mut first = true;
        self.block(&header, &r.body, |p, stmt| {
            p.room_stmt(stmt, first);
            first = false;
        });
    }

    fn room_stmt(&mut self, stmt: &ast::RoomStmt, first: bool) {
        match stmt {
            ast::RoomStmt::FloorDesign(s, _) => self.line(&format!("floor {}", string(s))),
            ast::RoomStmt::WallDesign(s, _) => self.line(&format!("walls {}", string(s))),
            ast::RoomStmt::FloorMaterial(s, _) => {
                self.line(&format!("floor material {}", string(s)));
            }
            ast::RoomStmt::WallMaterial(s, _) => self.line(&format!("wall material {}", string(s))),
            ast::RoomStmt::Corners(c) => {
                let mut text = "corners".to_string();
                if let Some((unit, _)) = c.unit {
                    let _ = write!(text, " in {}", unit.as_str());
                }
                for pt in &c.points {
                    let _ = write!(text, " ({}, {})", quantity(&pt.x), quantity(&pt.z));
                }
                self.line(&text);
            }
            ast::RoomStmt::Window(w) => {
                let mut text = format!(
                    "window {} {} {} x {}",
                    w.wall.name,
                    w.kind.name,
                    quantity(&w.width),
                    quantity(&w.height)
                );
                if let Some(c) = &w.count {
                    let _ = write!(text, ", count {}", quantity(c));
                }
                if let Some(s) = &w.sill {
                    let _ = write!(text, ", sill {}", quantity(s));
                }
                if let Some(a) = &w.asset {
                    let _ = write!(text, ", asset {}", string(a));
                }
                self.line(&text);
            }
            ast::RoomStmt::Object(o) => self.object("object", o),
            ast::RoomStmt::WallObject(o) => self.object("wall object", o),
            ast::RoomStmt::Ceiling(c) => {
                let header = format!("ceiling {}", string(&c.description));
                if c.body.is_empty() {
                    self.line(&header);
                } else {
                    self.object_block(&header, &c.body);
                }
            }
            ast::RoomStmt::Comment(c) => self.comment(c, first),
            ast::RoomStmt::Error(e) => self.line(&e.text),
            ast::RoomStmt::Blank(_) => self.blank_line(),
        }
    }

    fn object(&mut self, keyword: &str, o: &ast::Object) {
        let header = format!("{keyword} {} {}", o.id.name, string(&o.category));
        if o.has_block {
            self.object_block(&header, &o.body);
        } else {
            self.line(&header);
        }
    }

    fn object_block(&mut self, header: &str, body: &[ast::ObjectStmt]) {
        // A block of one simple statement stays on one line: `instance chair-1 { near table-0 }`.
        if let [only] = body {
            let simple = !matches!(
                only,
                ast::ObjectStmt::Instance(_)
                    | ast::ObjectStmt::OnTop(_)
                    | ast::ObjectStmt::Comment(_)
                    | ast::ObjectStmt::Error(_)
                    | ast::ObjectStmt::Blank(_)
            );
            if simple {
                let mut inner = Printer { out: String::new(), indent: 0 };
                inner.object_stmt(only, true);
                self.line(&format!("{header} {{ {} }}", inner.out.trim_end()));
                return;
            }
        }
        let mut first = true;
        self.block(header, body, |p, stmt| {
            p.object_stmt(stmt, first);
            first = false;
        });
    }

    fn object_stmt(&mut self, stmt: &ast::ObjectStmt, first: bool) {
        match stmt {
            ast::ObjectStmt::Describe(s, _) => self.line(&format!("describe {}", string(s))),
            ast::ObjectStmt::Size(s) => self.line(&format!(
                "size {} x {} x {}",
                quantity(&s.width),
                quantity(&s.depth),
                quantity(&s.height)
            )),
            ast::ObjectStmt::Count(n, variance, _) => {
                let mut text = format!("count {}", quantity(n));
                if let Some(v) = variance {
                    let _ = write!(text, " {}", v.name);
                }
                self.line(&text);
            }
            ast::ObjectStmt::Asset(s, _) => self.line(&format!("asset {}", string(s))),
            ast::ObjectStmt::Constraint(c) => match &c.target {
                Some(t) => self.line(&format!("{} {}", c.name.name, t.name)),
                None => self.line(&c.name.name),
            },
            ast::ObjectStmt::Above(t, _) => self.line(&format!("above {}", t.name)),
            ast::ObjectStmt::Height(q, _) => self.line(&format!("height {}", quantity(q))),
            ast::ObjectStmt::At(qs, _) => {
                let parts: Vec<String> = qs.iter().map(quantity).collect();
                self.line(&format!("at {}", parts.join(", ")));
            }
            ast::ObjectStmt::Facing(q, _) => self.line(&format!("facing {}", quantity(q))),
            ast::ObjectStmt::OnTop(t) => {
                let mut header = format!("on top {}", string(&t.item));
                if let Some(c) = &t.count {
                    let _ = write!(header, " x{}", c.text);
                }
                if let Some(v) = &t.variance {
                    let _ = write!(header, " {}", v.name);
                }
                if t.body.is_empty() {
                    self.line(&header);
                } else {
                    self.object_block(&header, &t.body);
                }
            }
            ast::ObjectStmt::Instance(i) => {
                self.object_block(&format!("instance {}", i.id.name), &i.body);
            }
            ast::ObjectStmt::Comment(c) => self.comment(c, first),
            ast::ObjectStmt::Error(e) => self.line(&e.text),
            ast::ObjectStmt::Blank(_) => self.blank_line(),
        }
    }

    fn door(&mut self, d: &ast::Door) {
        let mut text = format!("door {} -- {} : {}", d.from.name, d.to.name, d.kind.name);
        if let Some(size) = &d.size {
            let _ = write!(text, " {}", size.name);
        }
        if let Some(style) = &d.style {
            let _ = write!(text, " {}", string(style));
        }
        if let Some(asset) = &d.asset {
            let _ = write!(text, " asset {}", string(asset));
        }
        self.line(&text);
    }
}
