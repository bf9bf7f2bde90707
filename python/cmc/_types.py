"""Type names shared by the package's hints."""
from typing import Any, Dict

# A parsed JSON object: a run's summary.json, a store's record, an estimate as
# best_estimates.json holds it. Its keys are the file format's, documented where it is written.
Json = Dict[str, Any]
