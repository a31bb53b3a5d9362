/**
 * @file The tree-sitter grammar of `.holo`, holoc's scene language.
 *
 * It follows `grammar/holo.pest` (the parser's grammar, the authority) rule by rule: a file is
 * a list of items (`scene`, `room`, `door`), blocks hold statements one per line or separated
 * by `;`, line breaks are significant and spaces, tabs and comments are not. Where pest keeps a
 * line no statement matches as a `bad_line` for its diagnostic, tree-sitter makes an ERROR
 * node: the editor colours the rest of the file all the same.
 *
 * Words whose vocabulary the checker reads (directions, window types, door kinds and sizes,
 * variance) are `word`s, as in pest; names are `ident`s, aliased by where they stand:
 * `room_name` (declared), `room_ref` (a door's rooms), `object_name` (an object group or
 * instance, declared), `object_ref` (a relation's target, `above`).
 */

/// The statements of a block between `{` and `}`: one per line or separated by `;`.
function block($, statement) {
  return seq(
    '{',
    optional($._sep),
    optional(seq(statement, repeat(seq($._sep, statement)), optional($._sep))),
    '}',
  );
}

module.exports = grammar({
  name: 'holo',

  // Spaces, tabs, comments and a byte-order mark separate tokens; line breaks do not.
  extras: $ => [/[ \t]/, /\uFEFF/, $.comment],

  // Keywords are read as words, then told apart where the grammar expects them.
  word: $ => $.word,

  rules: {
    source_file: $ => seq(
      optional($._sep),
      optional(seq($._item, repeat(seq($._sep, $._item)), optional($._sep))),
    ),

    _item: $ => choice($.scene, $.room, $.door),

    // What separates statements: line breaks and semicolons.
    _sep: $ => repeat1(choice(/\r?\n/, /\r/, ';')),

    // ------------------------------------------------------------------------------------
    // Lexical rules.

    comment: _ => token(choice(
      seq('//', /[^\r\n]*/),
      seq('/*', /[^*]*\*+([^/*][^*]*\*+)*/, '/'),
    )),

    // An identifier: letters, digits, `_`, and inner `-` (`chair-1`).
    ident: _ => /[A-Za-z_][A-Za-z0-9_]*(-[A-Za-z0-9_]+)*/,

    // A vocabulary word (`north`, `fixed`, `varied`, `doorway`, `N/A`), checked by the checker.
    // None starts with `x` and a digit: that is the count of `on top "book" x2 varied`.
    word: _ => /[A-Za-wyz][A-Za-z0-9_\/-]*|x([A-Za-z_\/-][A-Za-z0-9_\/-]*)?/,

    number: _ => /-?[0-9]+(\.[0-9]+)?/,

    unit: _ => choice('cm', 'mm', 'm', 'deg', 'ft', 'in', 'rad'),

    quantity: $ => seq($.number, optional($.unit)),

    string: $ => seq(
      '"',
      repeat(choice($._string_content, $.escape_sequence)),
      token.immediate('"'),
    ),

    _string_content: _ => token.immediate(prec(1, /[^"\\\r\n]+/)),

    escape_sequence: _ => token.immediate(/\\(["\\nt]|u\{[0-9A-Fa-f]{1,6}\})/),

    // The multiplication sign between dimensions (`x` is not a keyword: `x2` is `x` and `2`).
    _times: $ => choice(alias(token(prec(2, 'x')), 'x'), '×'),

    // ------------------------------------------------------------------------------------
    // The scene block.

    scene: $ => seq('scene', optional(field('request', $.string)), block($, $._scene_statement)),

    _scene_statement: $ => choice($.wall_height, $.seed, $.ceiling_material, $.ceiling_design),

    wall_height: $ => seq('wall', 'height', $.quantity),

    seed: $ => seq('seed', $.quantity),

    ceiling_material: $ => seq('ceiling', 'material', $.string),

    ceiling_design: $ => seq('ceiling', $.string),

    // ------------------------------------------------------------------------------------
    // Rooms.

    room: $ => seq(
      'room',
      field('name', alias($.ident, $.room_name)),
      optional(field('label', $.string)),
      block($, $._room_statement),
    ),

    _room_statement: $ => choice(
      $.floor_material, $.wall_material, $.floor_design, $.wall_design, $.corners, $.window,
      $.wall_object, $.object, $.ceiling,
    ),

    floor_material: $ => seq('floor', 'material', $.string),

    wall_material: $ => seq('wall', 'material', $.string),

    floor_design: $ => seq('floor', $.string),

    wall_design: $ => seq('walls', $.string),

    corners: $ => seq('corners', optional($.corners_unit), repeat1($.point)),

    corners_unit: $ => seq('in', $.unit),

    point: $ => seq('(', $.quantity, ',', $.quantity, ')'),

    window: $ => seq(
      'window',
      field('wall', $.word),
      field('type', $.word),
      $.quantity,
      $._times,
      $.quantity,
      repeat(seq(',', choice($.window_count, $.window_sill, $.window_asset))),
    ),

    window_count: $ => seq('count', $.quantity),

    window_sill: $ => seq('sill', $.quantity),

    window_asset: $ => seq('asset', $.string),

    // ------------------------------------------------------------------------------------
    // Objects.

    object: $ => seq(
      'object',
      field('name', alias($.ident, $.object_name)),
      field('category', $.string),
      optional($.object_block),
    ),

    wall_object: $ => seq(
      'wall',
      'object',
      field('name', alias($.ident, $.object_name)),
      field('category', $.string),
      optional($.object_block),
    ),

    object_block: $ => block($, $._object_statement),

    _object_statement: $ => choice(
      $.describe, $.size, $.count, $.asset, $.on_top, $.instance, $.above, $.height, $.at,
      $.facing, $.constraint,
    ),

    describe: $ => seq('describe', $.string),

    size: $ => seq('size', $.quantity, $._times, $.quantity, $._times, $.quantity),

    count: $ => seq('count', $.quantity, optional($.word)),

    asset: $ => seq('asset', $.string),

    above: $ => seq('above', field('target', alias($.ident, $.object_ref))),

    height: $ => seq('height', $.quantity),

    at: $ => seq('at', $.quantity, repeat(seq(',', $.quantity))),

    facing: $ => seq('facing', $.quantity),

    // A relation name, in the paper's vocabulary (words separated by spaces).
    relation: _ => choice(
      token(prec(1, /in +front +of/)),
      'behind',
      token(prec(1, /side +of/)),
      token(prec(1, /left +of/)),
      token(prec(1, /right +of/)),
      'around',
      token(prec(1, /center +aligned/)),
      token(prec(1, /face +to/)),
      token(prec(1, /face +same +as/)),
      'near',
      'far',
      'edge',
      'middle',
    ),

    constraint: $ => seq($.relation, optional(field('target', alias($.ident, $.object_ref)))),

    on_top: $ => seq(
      'on',
      'top',
      $.string,
      optional($.on_top_count),
      optional($.word),
      optional($.object_block),
    ),

    // `x2`: the count of the things on top, the number right after the `x`.
    on_top_count: $ => seq($._times, alias(token.immediate(/-?[0-9]+(\.[0-9]+)?/), $.number)),

    instance: $ => seq('instance', field('name', alias($.ident, $.object_name)), $.object_block),

    ceiling: $ => seq('ceiling', $.string, optional($.object_block)),

    // ------------------------------------------------------------------------------------
    // Doors.

    door: $ => seq(
      'door',
      field('from', alias($.ident, $.room_ref)),
      '--',
      field('to', alias($.ident, $.room_ref)),
      ':',
      field('kind', $.word),
      optional(field('size', $.word)),
      optional(field('style', $.string)),
      optional($.door_asset),
    ),

    door_asset: $ => seq('asset', $.string),
  },
});
