"""motionsim's examples, shipped as package data (``motionsim.examples``): ``motionsim
examples DIR`` copies them out; ``README.md`` here lists every one."""
