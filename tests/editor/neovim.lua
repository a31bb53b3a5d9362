-- Drives `holoc lsp` from a real editor: neovim's built-in LSP client (0.7 and later), set up
-- by the book's Lua ($HOLO_SETUP, with `holoc` on the PATH). Opens $HOLO_SCENE, checks that its
-- filetype is `holo` and a client attached, waits for the server's first diagnostics, notes the
-- syntax colours of a few words and the word 0.7's completion (`vim.lsp.omnifunc`) replaces
-- after `near desk-`, turns `far bed-0` into a typo through the buffer (so neovim sends an
-- incremental change), waits for the diagnostic the server publishes for it, and writes what
-- neovim holds to $HOLO_OUT: `opened: <codes>`, then `syntax <word> <group>` and
-- `completion replaces <word>` lines, then `<line> <code> <message>` per diagnostic, then
-- `done`.
local scene = os.getenv("HOLO_SCENE")
local out_path = os.getenv("HOLO_OUT")
local out = {}

local function finish(status)
  table.insert(out, status)
  local f = assert(io.open(out_path, "w"))
  f:write(table.concat(out, "\n") .. "\n")
  f:close()
  vim.cmd("qall!")
end

local published = 0
local default_handler = vim.lsp.handlers["textDocument/publishDiagnostics"]
vim.lsp.handlers["textDocument/publishDiagnostics"] = function(err, result, ctx, config)
  published = published + 1
  return default_handler(err, result, ctx, config)
end

-- The book's setup, as written (book/src/cli/lsp.md), starts the server for the file.
dofile(os.getenv("HOLO_SETUP"))
vim.cmd("edit " .. vim.fn.fnameescape(scene))
local buf = vim.api.nvim_get_current_buf()
if vim.bo[buf].filetype ~= "holo" then
  finish("error: the filetype is `" .. vim.bo[buf].filetype .. "`, not holo")
  return
end
local function attached()
  return next(vim.lsp.buf_get_clients(buf)) ~= nil
end
if not vim.wait(30000, attached, 20) then
  finish("error: no client attached to the buffer")
  return
end
local client = next(vim.lsp.buf_get_clients(buf))

if not vim.wait(30000, function() return published > 0 end, 20) then
  finish("error: no diagnostics after opening")
  return
end
local function code_of(d)
  if d.code then return tostring(d.code) end
  local lsp = d.user_data and d.user_data.lsp
  return lsp and tostring(lsp.code) or "?"
end

local at_open = {}
for _, d in ipairs(vim.diagnostic.get(buf)) do
  table.insert(at_open, code_of(d))
end
table.insert(out, "opened: " .. table.concat(at_open, " "))

local lines = vim.api.nvim_buf_get_lines(buf, 0, -1, false)
-- The syntax group of the first `word` on a line that matches `line_pattern`.
local function syntax(line_pattern, word)
  for i, line in ipairs(lines) do
    if line:match(line_pattern) then
      local col = line:find(word, 1, true)
      local group = vim.fn.synIDattr(vim.fn.synID(i, col, 1), "name")
      table.insert(out, "syntax " .. word .. " " .. group)
      return
    end
  end
  table.insert(out, "syntax " .. word .. ": no line matches " .. line_pattern)
end
syntax("^room ", "room")
syntax("^room ", "bedroom")
syntax("left of bed%-0", "bed-0")
syntax("size 160 cm", "cm")
syntax("^door ", "\"white panel door\"")
-- What 0.7's `vim.lsp.omnifunc` replaces: the keyword before the cursor (`\k*$`).
local typed = "    near desk-"
local start = vim.fn.match(typed, "\\k*$")
table.insert(out, "completion replaces " .. typed:sub(start + 1))

for i, line in ipairs(lines) do
  if line:match("^%s*far bed%-0") then
    vim.api.nvim_buf_set_lines(buf, i - 1, i, false, { (line:gsub("far bed", "fra bed")) })
    break
  end
end

local found = vim.wait(30000, function()
  for _, d in ipairs(vim.diagnostic.get(buf)) do
    if code_of(d) == "E0102" then return true end
  end
  return false
end, 20)
for _, d in ipairs(vim.diagnostic.get(buf)) do
  local message = d.message:gsub("\n.*", "")
  table.insert(out, string.format("%d %s %s", d.lnum + 1, code_of(d), message))
end
vim.lsp.stop_client(client)
finish(found and "done" or "error: the typo's diagnostic never came")
