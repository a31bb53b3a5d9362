// Checks the TextMate grammar of `.holo` (editors/vscode/syntaxes/holo.tmLanguage.json) with
// the engine VS Code uses (the npm packages vscode-textmate and vscode-oniguruma, found through
// NODE_PATH) against holoc's semantic tokens.
//
// argv[2] names a file of cases: a line `file <path>` starts a file, each following line
// `<line> <column> <class>` (line from 1, column in UTF-16 code units from 0) is one token of
// the server; the innermost scope at the token's first character must be of that class.
// Prints one line per mismatch, `<path>:<line>:<column> expected <class>, got <scopes>`, then
// `seen <class> <class> ...` (the classes the grammar gave) and `done`.
"use strict";
const fs = require("fs");
const path = require("path");
const vsctm = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

/// The class of a scope, as the server names its tokens' classes.
function classOf(scope) {
  if (!scope || !scope.endsWith(".holo")) return null;
  if (scope.startsWith("comment.")) return "comment";
  if (scope.startsWith("string.") || scope.startsWith("constant.character.escape")) return "string";
  if (scope.startsWith("constant.numeric")) return "number";
  if (scope.startsWith("keyword.other.unit")) return "unit";
  if (scope.startsWith("keyword.operator")) return "operator";
  if (scope.includes(".room.")) return "room";
  if (scope.includes(".object.")) return "object";
  if (scope.startsWith("constant.language")) return "word";
  if (scope.startsWith("keyword.")) return "keyword";
  return null;
}

async function main() {
  const wasm = fs.readFileSync(path.join(path.dirname(require.resolve("vscode-oniguruma")), "onig.wasm"));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const grammarPath = path.join(__dirname, "..", "..", "editors", "vscode", "syntaxes", "holo.tmLanguage.json");
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scopeName) => {
      if (scopeName !== "source.holo") return null;
      return vsctm.parseRawGrammar(fs.readFileSync(grammarPath, "utf8"), grammarPath);
    },
  });
  const grammar = await registry.loadGrammar("source.holo");
  const out = [];
  const seen = new Set();
  let file = null;
  let lines = [];
  const cases = fs.readFileSync(process.argv[2], "utf8").split("\n");
  for (const c of cases) {
    if (c.startsWith("file ")) {
      file = c.slice(5);
      // Line breaks as the protocol counts them: `\r\n`, `\n` or a lone `\r`.
      const text = fs.readFileSync(file, "utf8");
      let state = vsctm.INITIAL;
      lines = text.split(/\r\n|\n|\r/).map((line) => {
        const result = grammar.tokenizeLine(line, state);
        state = result.ruleStack;
        return result.tokens;
      });
      continue;
    }
    const m = /^(\d+) (\d+) (\w+)$/.exec(c);
    if (!m) continue;
    const [line, column, expected] = [Number(m[1]), Number(m[2]), m[3]];
    const token = (lines[line - 1] || []).find((t) => t.startIndex <= column && column < t.endIndex);
    const scopes = token ? token.scopes : [];
    const got = classOf(scopes[scopes.length - 1]);
    if (got) seen.add(got);
    if (got !== expected) {
      out.push(`${file}:${line}:${column} expected ${expected}, got ${scopes.join(" ") || "nothing"}`);
    }
  }
  out.push("seen " + [...seen].sort().join(" "));
  out.push("done");
  process.stdout.write(out.join("\n") + "\n");
}

main().catch((e) => {
  process.stderr.write(String(e && e.stack || e) + "\n");
  process.exit(2);
});
