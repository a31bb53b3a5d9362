" holoc's `.holo` scenes: names such as `desk-0` are one word (completion, `*`, `w`), and
" comments start with `//`.
if exists("b:did_ftplugin")
  finish
endif
let b:did_ftplugin = 1
setlocal iskeyword+=-
setlocal commentstring=//\ %s
setlocal comments=://
let b:undo_ftplugin = "setlocal iskeyword< commentstring< comments<"
