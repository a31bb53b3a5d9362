-- Drives `holoc lsp` from a real editor: neovim's built-in LSP client (0.7 and later), set up
-- by the book's Lua ($HOLO_SETUP, with `holoc` on the PATH). Opens $HOLO_SCENE, checks that its
-- filetype is `holo` and a client attached, waits for the server's first diagnostics, turns
-- `far bed-0` into a typo through the buffer (so neovim sends an incremental change), waits for the diagnostic the
-- server publishes for it, and writes what neovim holds to $HOLO_OUT, one line per diagnostic:
-- `opened: <codes>`, then `<line> <code> <message>`, then `done`.
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
