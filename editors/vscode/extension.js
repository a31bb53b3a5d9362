// Starts `holoc lsp` for `.holo` files: the server gives diagnostics, hover, completion, rename,
// formatting, fixes and semantic tokens; the TextMate grammar colours the file before it answers.
"use strict";
const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration("holoc");
  const args = ["lsp"];
  if (!config.get("solve", true)) {
    args.push("--no-solve");
  }
  const server = { command: config.get("path", "holoc"), args };
  client = new LanguageClient(
    "holoc",
    "holoc",
    { run: server, debug: server },
    {
      documentSelector: [
        { scheme: "file", language: "holo" },
        { scheme: "untitled", language: "holo" },
      ],
      initializationOptions: { catalogs: config.get("catalogs", []) },
    },
  );
  context.subscriptions.push(client);
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
