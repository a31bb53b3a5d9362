" Vim and Neovim syntax of holoc's `.holo` scenes.
" The classes are those of `holoc lsp`'s semantic tokens (src/lsp/highlight.rs): keywords and
" relations, room and object names (declared, or named by a door, a relation or `above`), units,
" vocabulary words, strings, numbers, comments and the `x` of dimensions. `tests/editor.rs`
" checks them against the server's tokens in Neovim.
if exists("b:current_syntax")
  finish
endif

syn case match
syn iskeyword @,48-57,_,-

" Statement keywords (`in` is a match, so that the relation `in front of` can win over it).
" `room`, `door`, `object`, `instance` and `above` are matches below, followed by a name.
syn keyword holoKeyword scene wall walls height seed floor material corners window count sill
syn keyword holoKeyword asset ceiling describe size at facing on top
syn match holoKeyword "\<in\>"

" Vocabulary words the checker reads: directions, window types, door kinds and sizes, variance.
syn keyword holoWord north east south west fixed hung slider doorway doorframe open single
syn keyword holoWord double same varied

" Relations and the object they name.
syn match holoRelation "\<\%(in \+front \+of\|side \+of\|left \+of\|right \+of\|center \+aligned\|face \+to\|face \+same \+as\|behind\|around\|near\|far\|edge\|middle\)\>" nextgroup=holoObjectRef skipwhite
syn match holoObjectRef "\h[[:alnum:]_]*\%(-[[:alnum:]_]\+\)*" contained
syn match holoKeyword "\<above\>" nextgroup=holoObjectRef skipwhite

" Declarations.
syn match holoKeyword "\<room\>" nextgroup=holoRoomDecl skipwhite
syn match holoRoomDecl "\h[[:alnum:]_]*\%(-[[:alnum:]_]\+\)*" contained
syn match holoKeyword "\<\%(object\|instance\)\>" nextgroup=holoObjectDecl skipwhite
syn match holoObjectDecl "\h[[:alnum:]_]*\%(-[[:alnum:]_]\+\)*" contained

" A door's rooms: `door a -- b :` (`exterior` is the outside).
syn match holoKeyword "\<door\>" nextgroup=holoRoomRef skipwhite
syn match holoRoomRef "\h[[:alnum:]_]*\%(-[[:alnum:]_]\+\)*" contained nextgroup=holoDoorDash skipwhite
syn match holoDoorDash "--" contained nextgroup=holoRoomRef skipwhite

" Numbers with their units, and the `x` of dimensions and counts.
syn match holoNumber "\k\@<!-\?\d\+\%(\.\d\+\)\?" nextgroup=holoUnit skipwhite
syn match holoUnit "\%(cm\|mm\|m\|deg\|ft\|in\|rad\)\>" contained
syn match holoUnit "\%(\<corners\s\+in\s\+\)\@<=\%(cm\|mm\|m\)\>"
syn match holoOperator "\<x\ze\%(\d\|\s\|$\)\|×"
syn match holoNumber "\%(\<x\)\@<=\d\+"

syn region holoString start=+"+ skip=+\\\\\|\\"+ end=+"+ end=+$+ oneline
syn match holoComment "//.*$"
syn region holoComment start="/\*" end="\*/"

hi def link holoKeyword Keyword
hi def link holoRelation Keyword
hi def link holoWord Constant
hi def link holoRoomDecl Identifier
hi def link holoRoomRef Identifier
hi def link holoObjectDecl Function
hi def link holoObjectRef Function
hi def link holoNumber Number
hi def link holoUnit Type
hi def link holoOperator Operator
hi def link holoString String
hi def link holoComment Comment

let b:current_syntax = "holo"
