"""Build scripts for the course's other editions: slides, book and student edition.

Run them through make (`make slides`, `make book`, `make student`) or as modules
(`.venv/bin/python -m tools.slides`). Everything they write goes under build/.
"""
