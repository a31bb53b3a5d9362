; Highlights of `.holo`, holoc's scene language, with tree-sitter's standard capture names.
; Each class is the one `holoc lsp` gives the same word in its semantic tokens (the test
; tests/tree_sitter.rs checks every token of every example, corpus scene and book snippet):
; keywords and relations @keyword, room names @module, object names @variable, units @type,
; vocabulary words @constant, strings @string, numbers @number, comments @comment, `x` @operator.

(comment) @comment

(string) @string

(escape_sequence) @string.escape

(number) @number

(unit) @type

(word) @constant

(room_name) @module

(room_ref) @module

(object_name) @variable

(object_ref) @variable

(relation) @keyword

(corners_unit
  "in" @keyword)

[
  "scene"
  "room"
  "door"
  "wall"
  "walls"
  "height"
  "seed"
  "floor"
  "material"
  "corners"
  "window"
  "count"
  "sill"
  "asset"
  "object"
  "ceiling"
  "describe"
  "size"
  "above"
  "at"
  "facing"
  "on"
  "top"
  "instance"
] @keyword

[
  "x"
  "×"
] @operator

[
  "--"
  ":"
] @punctuation.delimiter

[
  ","
  ";"
] @punctuation.delimiter

[
  "{"
  "}"
  "("
  ")"
] @punctuation.bracket
