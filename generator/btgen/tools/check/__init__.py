"""`btgen check`: every BehaviorTree.CPP file of a repository, checked as the project loads it.

- `discovery`: the files found by content, what each is, and the loads that check them;
- `config`: `[tool.btgen]` / `btgen.toml`, found upwards;
- `codes`: the one table of diagnostic codes (docs/rules/ is generated from it by `rules_doc`);
- `runner`: the loads in one process, the findings, suppressions and selection;
- `formats`: text, JSON, SARIF 2.1.0, JUnit XML, GitHub annotations;
- `command`: the command line.
"""
