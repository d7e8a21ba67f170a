"""cfrdtools: the layer every script in tools/ shares (see tools/README.md).

decks   -- fixed-format card fields (I5, F10, A10, free reals)
runner  -- find bin/cfrd, write a deck, run it (one or many), timings
results -- open a .h5 and read its stages (docs/results.md)
"""
