-- Checks Vim's syntax of `.holo` (editors/vim, on the runtime path through $HOLO_RUNTIME) against
-- holoc's semantic tokens. $HOLO_CASES names a file of cases: a line `file <path>` opens a
-- file, each following line `<line> <byte column> <class>` (both from 1) is one token of the
-- server; the syntax group under the token's first character must be of that class. Writes to
-- $HOLO_OUT one line per mismatch, `<path>:<line>:<column> expected <class>, got <group>`,
-- then `seen <class> <class> ...` (the classes the syntax gave) and `done`.
vim.opt.runtimepath:append(os.getenv("HOLO_RUNTIME"))
-- Filetype detection ran before the folder was on the runtime path: read its rule now.
vim.cmd("augroup filetypedetect | runtime! ftdetect/holo.vim | augroup END")
vim.cmd("filetype plugin on")
vim.cmd("syntax on")
local classes = {
  holoKeyword = "keyword", holoRelation = "keyword",
  holoRoomDecl = "room", holoRoomRef = "room",
  holoObjectDecl = "object", holoObjectRef = "object",
  holoUnit = "unit", holoWord = "word", holoString = "string", holoNumber = "number",
  holoComment = "comment", holoOperator = "operator",
}
local out = {}
local seen = {}
local path = nil
for line in io.lines(os.getenv("HOLO_CASES")) do
  local file = line:match("^file (.*)$")
  if file then
    path = file
    vim.cmd("edit! " .. vim.fn.fnameescape(file))
    if vim.bo.filetype ~= "holo" then
      table.insert(out, file .. ": the filetype is `" .. vim.bo.filetype .. "`")
    end
  else
    local l, c, class = line:match("^(%d+) (%d+) (%a+)$")
    l, c = tonumber(l), tonumber(c)
    local group = vim.fn.synIDattr(vim.fn.synID(l, c, 1), "name")
    local got = classes[group]
    if got then seen[got] = true end
    if got ~= class and #out < 60 then
      table.insert(out, string.format("%s:%d:%d expected %s, got %s", path, l, c, class,
        group == "" and "nothing" or group))
    end
  end
end
local names = {}
for class in pairs(seen) do table.insert(names, class) end
table.sort(names)
table.insert(out, "seen " .. table.concat(names, " "))
table.insert(out, "done")
local f = assert(io.open(os.getenv("HOLO_OUT"), "w"))
f:write(table.concat(out, "\n") .. "\n")
f:close()
vim.cmd("qall!")
