"""One small module per CLI subcommand; each calls only the public API."""
