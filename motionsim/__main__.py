"""``python -m motionsim``: the same command line as the ``motionsim`` script."""

from motionsim.app.cli import main

if __name__ == "__main__":
    main()
