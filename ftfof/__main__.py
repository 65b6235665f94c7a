"""`python -m ftfof <stage>`: the same app as the `ftfof` console script."""

from stages.cli import main

main()
