"""The environment knowledge base linter (`btgen lint-kb`)."""
