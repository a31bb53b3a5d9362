; Highlights of `.holo` for Helix: editors/tree-sitter-holo/queries/highlights.scm with Helix's
; capture names (@namespace for rooms, @constant.numeric for numbers); tests/tree_sitter.rs holds
; the two to the same patterns and checks both against the server's semantic tokens.

(comment) @comment

(string) @string

(escape_sequence) @constant.character.escape

(number) @constant.numeric

(unit) @type

(word) @constant

(room_name) @namespace

(room_ref) @namespace

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
