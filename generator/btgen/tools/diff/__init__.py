"""`btgen diff`: do two missions (or one mission under two versions) behave the same?

product.py decides it (a breadth-first exploration of both missions driven by the same
leaf outcomes); command.py is the command line, the report and the counterexample files.
"""
