" `.holo` files are holoc's scenes.
autocmd BufRead,BufNewFile *.holo setfiletype holo
