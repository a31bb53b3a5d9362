-- Checks holoc's tree-sitter grammar with Neovim's own tree-sitter library, set up as the book's
-- plugin-free Neovim setup puts it: the parser compiled to $HOLO_SITE/parser/holo.so and the
-- queries copied to $HOLO_SITE/queries/holo/highlights.scm, $HOLO_SITE on the runtime path.
-- $HOLO_CASES names a file of cases as for syntax.lua: a line `file <path>` opens a file, each
-- following line `<line> <byte column> <class>` (both from 1) is one token of the server; the
-- innermost highlight capture over the token's first character must be of that class. Writes
-- to $HOLO_OUT one line per file with an ERROR or MISSING node and per mismatch, then
-- `seen <class> ...` (the classes the captures gave) and `done`.
vim.opt.runtimepath:append(os.getenv("HOLO_SITE"))
local classes = {
  keyword = "keyword", module = "room", variable = "object", type = "unit", constant = "word",
  string = "string", number = "number", comment = "comment", operator = "operator",
}
local out = {}
local seen = {}
local query = vim.treesitter.get_query("holo", "highlights")
local path = nil
local at = {}
local function problem(text)
  if #out < 60 then table.insert(out, text) end
end
for line in io.lines(os.getenv("HOLO_CASES")) do
  local file = line:match("^file (.*)$")
  if file then
    path = file
    vim.cmd("edit! " .. vim.fn.fnameescape(file))
    local tree = vim.treesitter.get_parser(0, "holo"):parse()[1]
    local root = tree:root()
    if root:has_error() then problem(file .. ": an ERROR or MISSING node") end
    -- The class of every byte a capture covers, the later (inner) capture over the earlier.
    at = {}
    for id, node in query:iter_captures(root, 0, 0, -1) do
      local class = classes[query.captures[id]:match("^[^.]+")]
      if class then
        local sr, sc, er, ec = node:range()
        for row = sr, er do
          local text = vim.api.nvim_buf_get_lines(0, row, row + 1, false)[1] or ""
          local first = row == sr and sc or 0
          local last = row == er and ec or #text
          at[row] = at[row] or {}
          for col = first, last - 1 do at[row][col] = class end
        end
      end
    end
  else
    local l, c, class = line:match("^(%d+) (%d+) (%a+)$")
    l, c = tonumber(l), tonumber(c)
    local got = at[l - 1] and at[l - 1][c - 1]
    if got then seen[got] = true end
    if got ~= class then
      problem(string.format("%s:%d:%d expected %s, got %s", path, l, c, class, got or "nothing"))
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
