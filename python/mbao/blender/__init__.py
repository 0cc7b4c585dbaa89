"""mbao in Blender: the add-on (mbao_bake/, which Blender imports), the bake it
asks of mbao (request), and its installer (install; `python -m mbao blender`)."""
