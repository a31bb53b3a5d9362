//! A reader of the subset of Python's pickle format that objathor's feature files use: a dict
//! of lists of strings and numpy arrays, pickled with protocols 2 to 5 by numpy 1
//! (`numpy.core.…`) or numpy 2 (`numpy._core.…`).
//!
//! The reader is a small pickle machine over an arena of nodes: it never runs Python code, it
//! only builds a tree of values and recognises numpy's two ways of rebuilding an array (a
//! `_reconstruct` call with a `BUILD` state, and protocol 5's `_frombuffer` call). Array bytes
//! are not copied: a node keeps the byte range of the file they sit in (protocol 2 writes them
//! as a latin-1 string, which is decoded into bytes of its own). Every malformed input is an
//! error with the byte offset, never a panic; sizes are checked against the bytes left before
//! anything is allocated.
//!
//! [`write()`] is the inverse for tests and benchmarks: it writes such a dict the way numpy does,
//! in any of the four protocols and with either module name.

use std::ops::Range;

/// What went wrong reading a pickle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PickleError {
    /// The byte offset in the file.
    pub offset: usize,
    /// What is wrong, in words.
    pub message: String,
}

impl std::fmt::Display for PickleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} (at byte {})", self.message, self.offset)
    }
}

/// One value of the pickle.
#[derive(Clone, Debug, PartialEq)]
enum Node {
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    /// Bytes that stand in the file, by range.
    Bytes(Range<usize>),
    List(Vec<usize>),
    Tuple(Vec<usize>),
    Dict(Vec<(usize, usize)>),
    Global(String, String),
    /// `func(*args)`, then `BUILD` with `state` when there is one.
    Object {
        func: usize,
        args: usize,
        state: Option<usize>,
    },
    /// The result of `NEWOBJ`: `cls.__new__(cls, *args)`.
    New {
        class: usize,
        args: usize,
        state: Option<usize>,
    },
}

/// A read pickle: its nodes and the top value.
#[derive(Debug)]
pub struct Pickle<'a> {
    data: Input<'a>,
    nodes: Vec<Node>,
    root: usize,
}

/// Where a pickle's bytes are: in memory, or in a file (of this length) read as the reader
/// goes. From a file, only the opcodes and their small arguments are read: the byte strings
/// (an array's elements) are passed over and kept by their place, so a feature file of 4 GiB
/// is read with the memory of its `uids` (issue 51).
#[derive(Clone, Copy, Debug)]
pub enum Input<'a> {
    /// The pickle's bytes.
    Bytes(&'a [u8]),
    /// A file and its length when it was opened.
    File(&'a std::fs::File, usize),
}

impl Input<'_> {
    fn len(&self) -> usize {
        match self {
            Input::Bytes(b) => b.len(),
            Input::File(_, n) => *n,
        }
    }
}

/// The longest string (or Fortran-order array, reordered in memory) the reader takes: 256 MiB.
/// Protocol 2 writes an array's bytes as latin-1 text, held twice while it is decoded; a
/// larger one is refused with these words rather than filling the memory.
pub const MAX_HELD_BYTES: usize = 256 * 1024 * 1024;

/// How much of a file the reader reads at once (an opcode's argument longer than this, a
/// string, is read on its own).
const CHUNK: usize = 64 * 1024;

/// The bytes `r` of `data` (within its length): borrowed from memory or from `buf`, the last
/// chunk read of a file (starting at byte `*buf_at`), or read on their own when larger.
fn fetch<'s>(
    data: Input<'s>,
    buf: &'s mut Vec<u8>,
    buf_at: &mut usize,
    r: Range<usize>,
) -> std::io::Result<std::borrow::Cow<'s, [u8]>> {
    use std::borrow::Cow;
    match data {
        Input::Bytes(b) => Ok(Cow::Borrowed(&b[r])),
        Input::File(file, len) => {
            if r.start >= *buf_at && r.end <= *buf_at + buf.len() {
                return Ok(Cow::Borrowed(&buf[r.start - *buf_at..r.end - *buf_at]));
            }
            if r.len() > CHUNK {
                let mut own = vec![0u8; r.len()];
                super::features::read_at(file, &mut own, r.start as u64)?;
                return Ok(Cow::Owned(own));
            }
            let n = CHUNK.min(len - r.start);
            buf.resize(n, 0);
            *buf_at = r.start;
            super::features::read_at(file, buf, r.start as u64)?;
            Ok(Cow::Borrowed(&buf[..r.len()]))
        }
    }
}

/// The elements of a numpy float16 or float32 array as they stand in the file (or decoded
/// beside it).
#[derive(Clone, Debug, PartialEq)]
pub struct F16Array {
    /// The array's shape.
    pub shape: Vec<usize>,
    /// Where the elements are: in the file, by byte range, or decoded.
    pub bytes: ArrayBytes,
    /// Whether the elements are big-endian (`>f2`, `>f4`).
    pub big_endian: bool,
    /// Bytes per element: 2 (float16) or 4 (float32).
    pub item: usize,
}

/// Where an array's bytes are.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayBytes {
    /// A byte range of the pickle's data (C order).
    InFile(Range<usize>),
    /// Bytes of their own (C order).
    Owned(Vec<u8>),
}

impl ArrayBytes {
    /// How many bytes there are.
    pub fn len(&self) -> usize {
        match self {
            ArrayBytes::InFile(r) => r.len(),
            ArrayBytes::Owned(v) => v.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

struct Machine<'a> {
    data: Input<'a>,
    /// The chunk of a file last read, and where it starts.
    buf: Vec<u8>,
    buf_at: usize,
    pos: usize,
    nodes: Vec<Node>,
    stack: Vec<usize>,
    marks: Vec<usize>,
    memo: std::collections::HashMap<u64, usize>,
}

fn err<T>(offset: usize, message: impl Into<String>) -> Result<T, PickleError> {
    Err(PickleError { offset, message: message.into() })
}

impl Machine<'_> {
    /// The bytes `r` (within the data; see [`Machine::take`]).
    fn read(&mut self, r: Range<usize>) -> Result<std::borrow::Cow<'_, [u8]>, PickleError> {
        let at = r.start;
        fetch(self.data, &mut self.buf, &mut self.buf_at, r).map_err(|e| PickleError {
            offset: at,
            message: format!("the file cannot be read: {e}"),
        })
    }

    fn take(&mut self, n: u64) -> Result<Range<usize>, PickleError> {
        let left = (self.data.len() - self.pos) as u64;
        if n > left {
            return err(self.pos, format!("the file ends inside a value of {n} bytes"));
        }
        let start = self.pos;
        self.pos += n as usize;
        Ok(start..self.pos)
    }

    fn uint(&mut self, width: usize) -> Result<u64, PickleError> {
        let r = self.take(width as u64)?;
        let mut v = 0u64;
        for (i, b) in self.read(r)?.iter().enumerate() {
            v |= u64::from(*b) << (8 * i);
        }
        Ok(v)
    }

    fn line(&mut self) -> Result<String, PickleError> {
        let start = self.pos;
        // In a file, a line (a module or a memo key) is looked for in the next chunk.
        let end = match self.data {
            Input::Bytes(b) => b.len(),
            Input::File(_, len) => len.min(start + CHUNK),
        };
        let (n, text) = {
            let window = self.read(start..end)?;
            let Some(n) = window.iter().position(|b| *b == b'\n') else {
                return err(start, "a text argument has no end of line");
            };
            (n, String::from_utf8(window[..n].to_vec()))
        };
        self.pos = start + n + 1;
        text.map_err(|_| PickleError { offset: start, message: "text is not UTF-8".into() })
    }

    fn push(&mut self, node: Node) {
        self.nodes.push(node);
        self.stack.push(self.nodes.len() - 1);
    }

    fn pop(&mut self, at: usize) -> Result<usize, PickleError> {
        if self.marks.last().is_some_and(|m| *m >= self.stack.len()) {
            return err(at, "an opcode takes a value across a mark");
        }
        match self.stack.pop() {
            Some(v) => Ok(v),
            None => err(at, "an opcode needs a value and the stack is empty"),
        }
    }

    fn pop_mark(&mut self, at: usize) -> Result<Vec<usize>, PickleError> {
        let Some(mark) = self.marks.pop() else {
            return err(at, "an opcode needs a mark and there is none");
        };
        Ok(self.stack.split_off(mark.min(self.stack.len())))
    }

    fn top(&self, at: usize) -> Result<usize, PickleError> {
        match self.stack.last() {
            Some(v) => Ok(*v),
            None => err(at, "an opcode needs a value and the stack is empty"),
        }
    }

    fn string(&mut self, width: usize) -> Result<(), PickleError> {
        let at = self.pos;
        let n = self.uint(width)?;
        let r = self.take(n)?;
        if r.len() > MAX_HELD_BYTES {
            return err(
                at,
                format!(
                    "a string of {n} bytes is longer than holoc reads ({} MiB; protocol 2 \
                     writes an array as such a string: save the file with protocol 4 or 5)",
                    MAX_HELD_BYTES >> 20
                ),
            );
        }
        let text = std::str::from_utf8(&self.read(r)?)
            .map(str::to_string)
            .map_err(|_| PickleError { offset: at, message: "a string is not UTF-8".into() })?;
        self.push(Node::Str(text));
        Ok(())
    }

    fn bytes(&mut self, width: usize) -> Result<(), PickleError> {
        let n = self.uint(width)?;
        let r = self.take(n)?;
        self.push(Node::Bytes(r));
        Ok(())
    }

    fn memo_put(&mut self, key: u64, at: usize) -> Result<(), PickleError> {
        let v = self.top(at)?;
        self.memo.insert(key, v);
        Ok(())
    }

    fn memo_get(&mut self, key: u64, at: usize) -> Result<(), PickleError> {
        match self.memo.get(&key) {
            Some(v) => {
                self.stack.push(*v);
                Ok(())
            }
            None => err(at, format!("memo entry {key} is read before it is written")),
        }
    }

    fn run(mut self) -> Result<(Vec<Node>, usize), PickleError> {
        loop {
            let at = self.pos;
            if at >= self.data.len() {
                return err(at, "the file ends before the pickle's STOP");
            }
            let op = self.read(at..at + 1)?[0];
            self.pos += 1;
            match op {
                0x80 => {
                    let proto = self.uint(1)?;
                    if proto > 5 {
                        return err(
                            at,
                            format!("pickle protocol {proto} is not read (2 to 5 are)"),
                        );
                    }
                }
                0x95 => {
                    self.uint(8)?;
                }
                b'.' => {
                    let root = self.pop(at)?;
                    return Ok((self.nodes, root));
                }
                b'}' => self.push(Node::Dict(Vec::new())),
                b']' => self.push(Node::List(Vec::new())),
                b')' => self.push(Node::Tuple(Vec::new())),
                b'(' => self.marks.push(self.stack.len()),
                b'N' => self.push(Node::None),
                0x88 => self.push(Node::Bool(true)),
                0x89 => self.push(Node::Bool(false)),
                b'K' => {
                    let v = self.uint(1)?;
                    self.push(Node::Int(v as i64));
                }
                b'M' => {
                    let v = self.uint(2)?;
                    self.push(Node::Int(v as i64));
                }
                b'J' => {
                    let v = self.uint(4)? as u32 as i32;
                    self.push(Node::Int(i64::from(v)));
                }
                0x8a | 0x8b => {
                    let n = self.uint(if op == 0x8a { 1 } else { 4 })?;
                    if n > 8 {
                        return err(at, "an integer larger than 64 bits");
                    }
                    let r = self.take(n)?;
                    let bytes = self.read(r)?;
                    let mut v: i64 = 0;
                    for (i, b) in bytes.iter().enumerate() {
                        v |= i64::from(*b) << (8 * i);
                    }
                    if n > 0 && n < 8 && bytes[n as usize - 1] & 0x80 != 0 {
                        v -= 1i64 << (8 * n);
                    }
                    self.push(Node::Int(v));
                }
                b'G' => {
                    let r = self.take(8)?;
                    let mut b = [0u8; 8];
                    b.copy_from_slice(&self.read(r)?);
                    self.push(Node::Float(f64::from_be_bytes(b)));
                }
                b'X' => self.string(4)?,
                0x8c => self.string(1)?,
                0x8d => self.string(8)?,
                b'B' | b'T' => self.bytes(4)?,
                b'C' | b'U' => self.bytes(1)?,
                0x8e | 0x96 => self.bytes(8)?,
                b't' => {
                    let items = self.pop_mark(at)?;
                    self.push(Node::Tuple(items));
                }
                0x85..=0x87 => {
                    let n = usize::from(op - 0x84);
                    let mut items = Vec::with_capacity(n);
                    for _ in 0..n {
                        items.push(self.pop(at)?);
                    }
                    items.reverse();
                    self.push(Node::Tuple(items));
                }
                b'a' => {
                    let v = self.pop(at)?;
                    let list = self.top(at)?;
                    match &mut self.nodes[list] {
                        Node::List(items) => items.push(v),
                        _ => return err(at, "APPEND to something that is not a list"),
                    }
                }
                b'e' => {
                    let items = self.pop_mark(at)?;
                    let list = self.top(at)?;
                    match &mut self.nodes[list] {
                        Node::List(l) => l.extend(items),
                        _ => return err(at, "APPENDS to something that is not a list"),
                    }
                }
                b's' => {
                    let v = self.pop(at)?;
                    let k = self.pop(at)?;
                    let dict = self.top(at)?;
                    match &mut self.nodes[dict] {
                        Node::Dict(d) => d.push((k, v)),
                        _ => return err(at, "SETITEM on something that is not a dict"),
                    }
                }
                b'u' => {
                    let items = self.pop_mark(at)?;
                    if items.len() % 2 != 0 {
                        return err(at, "SETITEMS with an odd number of values");
                    }
                    let dict = self.top(at)?;
                    match &mut self.nodes[dict] {
                        Node::Dict(d) => d.extend(items.chunks_exact(2).map(|p| (p[0], p[1]))),
                        _ => return err(at, "SETITEMS on something that is not a dict"),
                    }
                }
                b'c' => {
                    let module = self.line()?;
                    let name = self.line()?;
                    self.push(Node::Global(module, name));
                }
                0x93 => {
                    let name = self.pop(at)?;
                    let module = self.pop(at)?;
                    match (&self.nodes[module], &self.nodes[name]) {
                        (Node::Str(m), Node::Str(n)) => {
                            let g = Node::Global(m.clone(), n.clone());
                            self.push(g);
                        }
                        _ => return err(at, "STACK_GLOBAL needs two strings"),
                    }
                }
                b'R' => {
                    let args = self.pop(at)?;
                    let func = self.pop(at)?;
                    self.push(Node::Object { func, args, state: None });
                }
                0x81 => {
                    let args = self.pop(at)?;
                    let class = self.pop(at)?;
                    self.push(Node::New { class, args, state: None });
                }
                b'b' => {
                    let state = self.pop(at)?;
                    let obj = self.top(at)?;
                    match &mut self.nodes[obj] {
                        Node::Object { state: s, .. } | Node::New { state: s, .. } => {
                            *s = Some(state);
                        }
                        _ => return err(at, "BUILD on a value that is not an object"),
                    }
                }
                0x94 => {
                    let key = self.memo.len() as u64;
                    self.memo_put(key, at)?;
                }
                b'q' => {
                    let key = self.uint(1)?;
                    self.memo_put(key, at)?;
                }
                b'r' => {
                    let key = self.uint(4)?;
                    self.memo_put(key, at)?;
                }
                b'p' => {
                    let key = self.line()?.trim().parse().map_err(|_| PickleError {
                        offset: at,
                        message: "PUT needs a number".into(),
                    })?;
                    self.memo_put(key, at)?;
                }
                b'h' => {
                    let key = self.uint(1)?;
                    self.memo_get(key, at)?;
                }
                b'j' => {
                    let key = self.uint(4)?;
                    self.memo_get(key, at)?;
                }
                b'g' => {
                    let key = self.line()?.trim().parse().map_err(|_| PickleError {
                        offset: at,
                        message: "GET needs a number".into(),
                    })?;
                    self.memo_get(key, at)?;
                }
                b'0' => {
                    self.pop(at)?;
                }
                b'1' => {
                    self.pop_mark(at)?;
                }
                b'2' => {
                    let v = self.top(at)?;
                    self.stack.push(v);
                }
                0x97 | 0x98 => {
                    return err(at, "out-of-band buffers are not read: pickle in-band");
                }
                other => {
                    return err(at, format!("opcode 0x{other:02x} is not read by holoc"));
                }
            }
        }
    }
}

impl<'a> Pickle<'a> {
    /// Reads a pickle from its bytes.
    pub fn read(data: &'a [u8]) -> Result<Pickle<'a>, PickleError> {
        Pickle::read_input(Input::Bytes(data))
    }

    /// Reads a pickle from a file of `len` bytes without reading its byte strings (an
    /// array's elements), which stay on disk; [`Pickle::array_bytes`] and the rows made of it
    /// read them where they lie.
    pub fn read_file(file: &'a std::fs::File, len: usize) -> Result<Pickle<'a>, PickleError> {
        Pickle::read_input(Input::File(file, len))
    }

    /// Where the pickle's bytes are.
    pub fn input(&self) -> Input<'a> {
        self.data
    }

    fn read_input(data: Input<'a>) -> Result<Pickle<'a>, PickleError> {
        let machine = Machine {
            data,
            buf: Vec::new(),
            buf_at: 0,
            pos: 0,
            nodes: Vec::new(),
            stack: Vec::new(),
            marks: Vec::new(),
            memo: std::collections::HashMap::new(),
        };
        let (nodes, root) = machine.run()?;
        Ok(Pickle { data, nodes, root })
    }

    /// The keys of the top-level dict, in file order (`None` when the top value is no dict).
    pub fn keys(&self) -> Option<Vec<String>> {
        match &self.nodes[self.root] {
            Node::Dict(items) => Some(
                items
                    .iter()
                    .filter_map(|(k, _)| match &self.nodes[*k] {
                        Node::Str(s) => Some(s.clone()),
                        _ => None,
                    })
                    .collect(),
            ),
            _ => None,
        }
    }

    fn get(&self, key: &str) -> Option<usize> {
        match &self.nodes[self.root] {
            Node::Dict(items) => items
                .iter()
                .rev()
                .find(|(k, _)| matches!(&self.nodes[*k], Node::Str(s) if s == key))
                .map(|(_, v)| *v),
            _ => None,
        }
    }

    /// The list of strings under `key` of the top-level dict (a list, a tuple or a numpy array
    /// of unicode strings); `Ok(None)` when there is no such key.
    pub fn strings(&self, key: &str) -> Result<Option<Vec<String>>, String> {
        let Some(id) = self.get(key) else { return Ok(None) };
        match &self.nodes[id] {
            Node::List(items) | Node::Tuple(items) => items
                .iter()
                .map(|i| match &self.nodes[*i] {
                    Node::Str(s) => Ok(s.clone()),
                    _ => Err(format!("`{key}` holds something that is not a string")),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
            _ => {
                let array = self.array(id).map_err(|e| format!("`{key}`: {e}"))?;
                let (kind, width, big) = array.dtype;
                if kind != 'U' {
                    return Err(format!("`{key}` is neither a list of strings nor a string array"));
                }
                let bytes = self.read_array(&array.bytes).map_err(|e| format!("`{key}`: {e}"))?;
                let width_bytes = width * 4;
                if width_bytes == 0 || bytes.len() % width_bytes != 0 {
                    return Err(format!("`{key}`: the string array's bytes do not fit its type"));
                }
                let mut out = Vec::with_capacity(bytes.len() / width_bytes);
                for chunk in bytes.chunks_exact(width_bytes) {
                    let mut s = String::new();
                    for c in chunk.chunks_exact(4) {
                        let b = [c[0], c[1], c[2], c[3]];
                        let code = if big { u32::from_be_bytes(b) } else { u32::from_le_bytes(b) };
                        if code == 0 {
                            break;
                        }
                        s.push(char::from_u32(code).ok_or_else(|| {
                            format!("`{key}`: a string holds an invalid character")
                        })?);
                    }
                    out.push(s);
                }
                Ok(Some(out))
            }
        }
    }

    /// The float16 or float32 array under `key` of the top-level dict; `Ok(None)` when there is
    /// no such key.
    pub fn f16_array(&self, key: &str) -> Result<Option<F16Array>, String> {
        let Some(id) = self.get(key) else { return Ok(None) };
        let array = self.array(id).map_err(|e| format!("`{key}`: {e}"))?;
        let (kind, width, big_endian) = array.dtype;
        if kind != 'f' || !matches!(width, 2 | 4) {
            return Err(format!(
                "`{key}` is an array of `{kind}{width}`, not of float16 (`f2`) or float32 (`f4`)"
            ));
        }
        let len = array.bytes.len();
        // The shape's size with overflow checked: a shape whose product wraps (to zero, say)
        // would otherwise pass for an array of the bytes present.
        let Some(needed) = element_bytes(&array.shape, width) else {
            return Err(format!(
                "`{key}`: its shape {:?} holds more elements than any file can, the pickle holds \
                 {len} bytes",
                array.shape
            ));
        };
        if needed != len {
            return Err(format!(
                "`{key}`: its shape {:?} needs {needed} bytes, the pickle holds {len}",
                array.shape
            ));
        }
        let bytes = if array.fortran && array.shape.len() > 1 {
            if len > MAX_HELD_BYTES {
                return Err(format!(
                    "`{key}`: a Fortran-order array of more than {} MiB is not read (it is \
                     reordered in memory); save it in C order",
                    MAX_HELD_BYTES >> 20
                ));
            }
            let held = self.read_array(&array.bytes).map_err(|e| format!("`{key}`: {e}"))?;
            ArrayBytes::Owned(fortran_to_c(&held, &array.shape, width))
        } else {
            array.bytes
        };
        Ok(Some(F16Array { shape: array.shape, bytes, big_endian, item: width }))
    }

    /// The bytes an array's elements are in (none when they are in a file that cannot be
    /// read: see [`Pickle::read_array`]).
    pub fn array_bytes<'b>(&'b self, bytes: &'b ArrayBytes) -> std::borrow::Cow<'b, [u8]> {
        self.read_array(bytes).unwrap_or_default()
    }

    /// The bytes an array's elements are in, read from the file when they are there.
    ///
    /// # Errors
    /// The file cannot be read.
    pub fn read_array<'b>(
        &'b self,
        bytes: &'b ArrayBytes,
    ) -> Result<std::borrow::Cow<'b, [u8]>, String> {
        use std::borrow::Cow;
        match (bytes, self.data) {
            (ArrayBytes::Owned(v), _) => Ok(Cow::Borrowed(v)),
            (ArrayBytes::InFile(r), Input::Bytes(b)) => Ok(Cow::Borrowed(&b[r.clone()])),
            (ArrayBytes::InFile(r), Input::File(file, _)) => {
                let mut own = vec![0u8; r.len()];
                super::features::read_at(file, &mut own, r.start as u64)
                    .map_err(|e| format!("the file cannot be read: {e}"))?;
                Ok(Cow::Owned(own))
            }
        }
    }

    fn global(&self, id: usize) -> Option<(&str, &str)> {
        match &self.nodes[id] {
            Node::Global(m, n) => Some((m.as_str(), n.as_str())),
            _ => None,
        }
    }

    fn int(&self, id: usize) -> Option<i64> {
        match &self.nodes[id] {
            Node::Int(v) => Some(*v),
            Node::Bool(b) => Some(i64::from(*b)),
            _ => None,
        }
    }

    fn items(&self, id: usize) -> Option<&[usize]> {
        match &self.nodes[id] {
            Node::Tuple(v) | Node::List(v) => Some(v),
            _ => None,
        }
    }

    fn shape(&self, id: usize) -> Result<Vec<usize>, String> {
        let items = self.items(id).ok_or("the shape is not a tuple")?;
        items
            .iter()
            .map(|i| {
                self.int(*i)
                    .and_then(|v| usize::try_from(v).ok())
                    .ok_or_else(|| "the shape holds something that is not a size".to_string())
            })
            .collect()
    }

    /// A dtype node: `(kind, item size, big-endian)`.
    fn dtype(&self, id: usize) -> Result<(char, usize, bool), String> {
        let Node::Object { func, args, state } = &self.nodes[id] else {
            return Err("the array's type is not a numpy dtype".into());
        };
        if self.global(*func) != Some(("numpy", "dtype")) {
            return Err("the array's type is not a numpy dtype".into());
        }
        let name = self
            .items(*args)
            .and_then(|a| a.first())
            .and_then(|n| match &self.nodes[*n] {
                Node::Str(s) => Some(s.clone()),
                _ => None,
            })
            .ok_or("the numpy dtype has no name")?;
        let order = state
            .and_then(|s| self.items(s))
            .and_then(|s| s.get(1))
            .and_then(|o| match &self.nodes[*o] {
                Node::Str(s) => Some(s.clone()),
                _ => None,
            })
            .unwrap_or_else(|| "|".to_string());
        let big = match order.as_str() {
            ">" => true,
            "<" | "|" => false,
            "=" => cfg!(target_endian = "big"),
            other => return Err(format!("unknown byte order `{other}` of the numpy dtype")),
        };
        let mut chars = name.chars();
        let kind = chars.next().ok_or("the numpy dtype has an empty name")?;
        let width: usize = chars.as_str().parse().map_err(|_| {
            format!("the numpy dtype `{name}` is not one holoc reads (float16 `f2`, float32 `f4`, strings `U`)")
        })?;
        Ok((kind, width, big))
    }

    fn buffer(&self, id: usize) -> Result<ArrayBytes, String> {
        match &self.nodes[id] {
            Node::Bytes(r) => Ok(ArrayBytes::InFile(r.clone())),
            Node::Object { func, args, .. }
                if self.global(*func) == Some(("_codecs", "encode")) =>
            {
                // Protocol 2: `_codecs.encode(text, "latin1")`.
                let a = self.items(*args).ok_or("bad `_codecs.encode` arguments")?;
                let (Some(Node::Str(text)), Some(Node::Str(enc))) =
                    (a.first().map(|i| &self.nodes[*i]), a.get(1).map(|i| &self.nodes[*i]))
                else {
                    return Err("bad `_codecs.encode` arguments".into());
                };
                if enc != "latin1" && enc != "latin-1" {
                    return Err(format!("bytes encoded as `{enc}`, not latin-1"));
                }
                text.chars()
                    .map(|c| u8::try_from(u32::from(c)).map_err(|_| "a latin-1 byte above 255"))
                    .collect::<Result<Vec<u8>, _>>()
                    .map(ArrayBytes::Owned)
                    .map_err(str::to_string)
            }
            Node::Object { func, args, .. }
                if matches!(self.global(*func), Some(("builtins" | "__builtin__", "bytes"))) =>
            {
                // An empty bytes object in protocol 2.
                if self.items(*args).is_some_and(<[usize]>::is_empty) {
                    Ok(ArrayBytes::Owned(Vec::new()))
                } else {
                    Err("bytes built from arguments holoc does not read".into())
                }
            }
            _ => Err("the array's data is not bytes".into()),
        }
    }

    fn array(&self, id: usize) -> Result<RawArray, String> {
        let Node::Object { func, args, state } = &self.nodes[id] else {
            return Err("not a numpy array".into());
        };
        match self.global(*func) {
            Some(("numpy.core.multiarray" | "numpy._core.multiarray", "_reconstruct")) => {
                let state = state.ok_or("a numpy array without its state")?;
                let s = self.items(state).ok_or("a numpy array's state is not a tuple")?;
                let [_, shape, dtype, fortran, data] = s else {
                    return Err("a numpy array's state does not have five parts".into());
                };
                Ok(RawArray {
                    shape: self.shape(*shape)?,
                    dtype: self.dtype(*dtype)?,
                    fortran: self.int(*fortran).unwrap_or(0) != 0,
                    bytes: self.buffer(*data)?,
                })
            }
            Some(("numpy.core.numeric" | "numpy._core.numeric", "_frombuffer")) => {
                let a = self.items(*args).ok_or("bad `_frombuffer` arguments")?;
                let [buf, dtype, shape, order] = a else {
                    return Err("`_frombuffer` does not have four arguments".into());
                };
                let fortran = matches!(&self.nodes[*order], Node::Str(o) if o == "F");
                Ok(RawArray {
                    shape: self.shape(*shape)?,
                    dtype: self.dtype(*dtype)?,
                    fortran,
                    bytes: self.buffer(*buf)?,
                })
            }
            Some((m, n)) => Err(format!("`{m}.{n}` is not a numpy array constructor")),
            None => Err("not a numpy array".into()),
        }
    }
}

struct RawArray {
    shape: Vec<usize>,
    dtype: (char, usize, bool),
    fortran: bool,
    bytes: ArrayBytes,
}

/// The bytes of an array of `shape` with elements of `item` bytes, or `None` when the product
/// overflows.
pub(crate) fn element_bytes(shape: &[usize], item: usize) -> Option<usize> {
    shape.iter().try_fold(item, |n, d| n.checked_mul(*d))
}

/// The elements of a Fortran-order array in C order (`bytes` holds exactly the elements of
/// `shape`, which [`Pickle::f16_array`] checks first).
fn fortran_to_c(bytes: &[u8], shape: &[usize], item: usize) -> Vec<u8> {
    let n: usize = shape.iter().product();
    let mut out = vec![0u8; n * item];
    // Fortran strides: the first index moves fastest.
    let mut f_strides = vec![1usize; shape.len()];
    for k in 1..shape.len() {
        f_strides[k] = f_strides[k - 1] * shape[k - 1];
    }
    let mut index = vec![0usize; shape.len()];
    for c in 0..n {
        let f: usize = index.iter().zip(&f_strides).map(|(i, s)| i * s).sum();
        out[c * item..(c + 1) * item].copy_from_slice(&bytes[f * item..(f + 1) * item]);
        for k in (0..shape.len()).rev() {
            index[k] += 1;
            if index[k] < shape[k] {
                break;
            }
            index[k] = 0;
        }
    }
    out
}

/// The float32 value of the float16 with these bits (exact).
pub fn f16_to_f32(bits: u16) -> f32 {
    let sign = u32::from(bits >> 15) << 31;
    let exp = u32::from((bits >> 10) & 0x1f);
    let frac = u32::from(bits & 0x3ff);
    let v = match (exp, frac) {
        (0, 0) => sign,
        (0, _) => {
            // Subnormal: frac × 2^-24, exactly representable in f32.
            let magnitude = frac as f32 * f32::from_bits(0x3380_0000);
            return if sign != 0 { -magnitude } else { magnitude };
        }
        (0x1f, 0) => sign | 0x7f80_0000,
        (0x1f, _) => sign | 0x7fc0_0000 | (frac << 13),
        _ => sign | ((exp + 112) << 23) | (frac << 13),
    };
    f32::from_bits(v)
}

/// The float16 nearest to `value` (ties to even), as bits.
pub fn f32_to_f16(value: f32) -> u16 {
    let x = value.to_bits();
    let sign = ((x >> 16) & 0x8000) as u16;
    let exp = ((x >> 23) & 0xff) as i32;
    let frac = x & 0x007f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if frac != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let mant = frac | 0x0080_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rest = mant & ((1u32 << shift) - 1);
        let mut h = mant >> shift;
        if rest > half || (rest == half && h & 1 == 1) {
            h += 1;
        }
        return sign | h as u16;
    }
    let mut h = ((e as u32) << 10) | (frac >> 13);
    let rest = frac & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && h & 1 == 1) {
        h += 1;
    }
    sign | h as u16
}

/// The numpy module names an array is written with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NumpyModules {
    /// numpy 1: `numpy.core.multiarray`, `numpy.core.numeric`.
    Core,
    /// numpy 2: `numpy._core.multiarray`, `numpy._core.numeric`.
    UnderscoreCore,
}

/// A value [`write()`] can write.
#[derive(Clone, Debug)]
pub enum Value {
    /// A list of strings.
    Strings(Vec<String>),
    /// A float16 array: its shape and its elements (as float16 bits), C order.
    F16 {
        /// The shape.
        shape: Vec<usize>,
        /// The elements.
        bits: Vec<u16>,
    },
    /// A float32 array: its shape and its elements, C order.
    F32 {
        /// The shape.
        shape: Vec<usize>,
        /// The elements.
        values: Vec<f32>,
    },
}

/// Writes a dict of string lists and float16 arrays as numpy and Python's pickle do, with
/// `protocol` (2 to 5) and the module names of numpy 1 or 2. For tests and benchmarks.
pub fn write(items: &[(&str, Value)], protocol: u8, modules: NumpyModules) -> Vec<u8> {
    let mut w = Writer { out: Vec::new(), protocol, memo: 0 };
    w.out.extend([0x80, protocol]);
    w.out.push(b'}');
    w.memoize();
    w.out.push(b'(');
    let core = match modules {
        NumpyModules::Core => "numpy.core",
        NumpyModules::UnderscoreCore => "numpy._core",
    };
    for (key, value) in items {
        w.str(key);
        match value {
            Value::Strings(list) => {
                w.out.push(b']');
                w.memoize();
                w.out.push(b'(');
                for s in list {
                    w.str(s);
                }
                w.out.push(b'e');
            }
            Value::F16 { shape, bits } => {
                let data: Vec<u8> = bits.iter().flat_map(|b| b.to_le_bytes()).collect();
                w.array(core, shape, &data, "f2");
            }
            Value::F32 { shape, values } => {
                let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
                w.array(core, shape, &data, "f4");
            }
        }
    }
    w.out.push(b'u');
    w.out.push(b'.');
    w.out
}

impl Writer {
    /// A numpy array of `shape` with the little-endian elements `data` of type `dtype`.
    fn array(&mut self, core: &str, shape: &[usize], data: &[u8], dtype: &str) {
        if self.protocol >= 5 {
            self.global(&format!("{core}.numeric"), "_frombuffer");
            self.out.push(b'(');
            self.out.push(0x96);
            self.out.extend((data.len() as u64).to_le_bytes());
            self.out.extend(data);
            self.memoize();
            self.dtype(dtype);
            self.shape(shape);
            self.str("C");
            self.out.push(b't');
            self.memoize();
            self.out.push(b'R');
            self.memoize();
        } else {
            self.global(&format!("{core}.multiarray"), "_reconstruct");
            self.global("numpy", "ndarray");
            self.out.extend([b'K', 0, 0x85]);
            self.memoize();
            self.bytes(b"b");
            self.out.push(0x87);
            self.memoize();
            self.out.push(b'R');
            self.memoize();
            self.out.extend([b'(', b'K', 1]);
            self.shape(shape);
            self.dtype(dtype);
            self.out.push(0x89);
            self.bytes(data);
            self.out.push(b't');
            self.memoize();
            self.out.push(b'b');
        }
    }
}

struct Writer {
    out: Vec<u8>,
    protocol: u8,
    memo: u32,
}

impl Writer {
    fn memoize(&mut self) {
        if self.protocol >= 4 {
            self.out.push(0x94);
        } else if self.memo < 256 {
            self.out.extend([b'q', self.memo as u8]);
        } else {
            self.out.push(b'r');
            self.out.extend(self.memo.to_le_bytes());
        }
        self.memo += 1;
    }

    fn str(&mut self, s: &str) {
        if self.protocol >= 4 && s.len() < 256 {
            self.out.extend([0x8c, s.len() as u8]);
        } else {
            self.out.push(b'X');
            self.out.extend((s.len() as u32).to_le_bytes());
        }
        self.out.extend(s.as_bytes());
        self.memoize();
    }

    fn global(&mut self, module: &str, name: &str) {
        if self.protocol >= 4 {
            self.str(module);
            self.str(name);
            self.out.push(0x93);
        } else {
            self.out.push(b'c');
            self.out.extend(module.as_bytes());
            self.out.push(b'\n');
            self.out.extend(name.as_bytes());
            self.out.push(b'\n');
        }
        self.memoize();
    }

    fn bytes(&mut self, data: &[u8]) {
        if self.protocol == 2 {
            // As Python does: `_codecs.encode(data.decode("latin1"), "latin1")`.
            self.global("_codecs", "encode");
            let text: String = data.iter().map(|b| char::from(*b)).collect();
            self.str(&text);
            self.str("latin1");
            self.out.push(0x86);
            self.memoize();
            self.out.push(b'R');
        } else if data.len() < 256 {
            self.out.extend([b'C', data.len() as u8]);
            self.out.extend(data);
        } else if let Ok(n) = u32::try_from(data.len()) {
            self.out.push(b'B');
            self.out.extend(n.to_le_bytes());
            self.out.extend(data);
        } else {
            self.out.push(0x8e);
            self.out.extend((data.len() as u64).to_le_bytes());
            self.out.extend(data);
        }
        self.memoize();
    }

    fn dtype(&mut self, name: &str) {
        self.global("numpy", "dtype");
        self.str(name);
        self.out.extend([0x89, 0x88, 0x87]);
        self.memoize();
        self.out.push(b'R');
        self.memoize();
        self.out.extend([b'(', b'K', 3]);
        self.str("<");
        self.out.extend([b'N', b'N', b'N']);
        self.out.push(b'J');
        self.out.extend((-1i32).to_le_bytes());
        self.out.push(b'J');
        self.out.extend((-1i32).to_le_bytes());
        self.out.extend([b'K', 0, b't']);
        self.memoize();
        self.out.push(b'b');
    }

    fn shape(&mut self, shape: &[usize]) {
        self.out.push(b'(');
        for d in shape {
            if let Ok(b) = u8::try_from(*d) {
                self.out.extend([b'K', b]);
            } else if let Ok(v) = i32::try_from(*d) {
                self.out.push(b'J');
                self.out.extend(v.to_le_bytes());
            } else {
                // `LONG1`: eight bytes, little-endian, two's complement (a size past 2^63 reads
                // back as a negative number, which the reader refuses).
                self.out.extend([0x8a, 8]);
                self.out.extend((*d as u64).to_le_bytes());
            }
        }
        self.out.push(b't');
        self.memoize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_conversions_are_exact_both_ways() {
        for bits in 0..=u16::MAX {
            let v = f16_to_f32(bits);
            if v.is_nan() {
                assert!(f16_to_f32(f32_to_f16(v)).is_nan());
            } else {
                assert_eq!(f32_to_f16(v), bits, "{bits:#06x} → {v}");
            }
        }
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x0001), 5.960_464_5e-8);
        assert_eq!(f32_to_f16(1e-7), 0x0002);
        assert_eq!(f32_to_f16(1e6), 0x7c00);
    }

    #[test]
    fn round_trips_every_protocol_and_module_name() {
        let uids = vec!["a".repeat(32), "b".repeat(32)];
        let bits: Vec<u16> = (0..12).map(|i| f32_to_f16(i as f32 / 4.0 - 1.0)).collect();
        for protocol in 2..=5 {
            for modules in [NumpyModules::Core, NumpyModules::UnderscoreCore] {
                let data = write(
                    &[
                        ("uids", Value::Strings(uids.clone())),
                        ("img_features", Value::F16 { shape: vec![2, 2, 3], bits: bits.clone() }),
                        (
                            "text_features",
                            Value::F16 { shape: vec![2, 3], bits: bits[..6].to_vec() },
                        ),
                    ],
                    protocol,
                    modules,
                );
                let p = Pickle::read(&data).expect("reads");
                assert_eq!(p.strings("uids").expect("ok"), Some(uids.clone()));
                let a = p.f16_array("img_features").expect("ok").expect("there");
                assert_eq!(a.shape, vec![2, 2, 3]);
                let got: Vec<u16> = p
                    .array_bytes(&a.bytes)
                    .chunks_exact(2)
                    .map(|c| u16::from_le_bytes([c[0], c[1]]))
                    .collect();
                assert_eq!(got, bits, "protocol {protocol} {modules:?}");
                let t = p.f16_array("text_features").expect("ok").expect("there");
                assert_eq!(t.shape, vec![2, 3]);
                assert_eq!(p.f16_array("missing"), Ok(None));
            }
        }
    }

    #[test]
    fn bad_inputs_are_errors_not_panics() {
        let good = write(
            &[("x", Value::F16 { shape: vec![2, 2], bits: vec![1, 2, 3, 4] })],
            4,
            NumpyModules::Core,
        );
        for cut in 0..good.len() {
            let _ = Pickle::read(&good[..cut]);
        }
        for i in 0..good.len() {
            for b in [0u8, 0xff, b'.', b'(', b'e', 0x93] {
                let mut bad = good.clone();
                bad[i] = b;
                if let Ok(p) = Pickle::read(&bad) {
                    let _ = p.f16_array("x");
                    let _ = p.strings("x");
                }
            }
        }
        assert!(Pickle::read(b"\x80\x06.").is_err());
        assert!(Pickle::read(b"").is_err());
    }

    #[test]
    fn fortran_order_is_turned_into_c_order() {
        // A 2×3 array [[0, 1, 2], [3, 4, 5]] in Fortran order is 0 3 1 4 2 5.
        let f: Vec<u8> = [0u8, 3, 1, 4, 2, 5].iter().flat_map(|v| [*v, 0]).collect();
        let c = fortran_to_c(&f, &[2, 3], 2);
        let got: Vec<u8> = c.chunks_exact(2).map(|p| p[0]).collect();
        assert_eq!(got, vec![0, 1, 2, 3, 4, 5]);
    }
}
