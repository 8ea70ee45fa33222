"""``python -m sphfem_cli.study CASE_DIR``: run one mesh-study case (sphfem_cli.study.runner.run_case)."""
import sys

from .runner import main

sys.exit(main())
