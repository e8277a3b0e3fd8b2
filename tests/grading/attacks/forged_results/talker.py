"""A4 forged results: write a perfect results.json wherever the grader might look, then exit."""
import json
import os

FAKE = json.dumps({"score": 10, "tests": [{"name": "0.1", "score": 10, "max_score": 10}]})
targets = ["results.json", "../results.json", "../../results.json", "/autograder/results/results.json",
           os.path.expanduser("~/../results.json"), "/tmp/results.json"]
targets += [os.path.join(os.environ.get("DDES_FORGE_DIR", "/nonexistent"), "results.json")]
for path in targets:
    try:
        with open(path, "w") as f:
            f.write(FAKE)
        print("wrote", path)
    except OSError as exc:
        print("refused", path, type(exc).__name__)
