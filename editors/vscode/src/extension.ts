// Starts `ger lsp` for G-code files: everything the editor shows comes from
// the server (diagnostics, hover, definitions, symbols, fixes, completion).
import * as vscode from "vscode";
import { LanguageClient, LanguageClientOptions, ServerOptions } from "vscode-languageclient/node";

let client: LanguageClient | undefined;

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  const config = vscode.workspace.getConfiguration("ger");
  const command = config.get<string>("path", "ger");
  const args = ["lsp", "--stdio", ...config.get<string[]>("arguments", [])];
  const server: ServerOptions = { command, args };
  const clientOptions: LanguageClientOptions = {
    documentSelector: [{ scheme: "file", language: "gcode" }],
    initializationOptions: { inlayHints: config.get<boolean>("inlayHints", false) },
  };
  client = new LanguageClient("ger", "ger", server, clientOptions);
  context.subscriptions.push(client);
  await client.start();
}

export async function deactivate(): Promise<void> {
  await client?.stop();
}
