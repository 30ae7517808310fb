"""What a process that is not Python needs to host pythonfmu's binary, as NAME=VALUE lines.

pythonfmu's linux64 binary calls the Python C API without linking libpython (inside a Python
master the interpreter provides it), so a native master must preload this Python's shared
library, and the embedded interpreter must be told where its standard library is, since it
cannot derive it from the master's executable. The FMU carries the pythonfmu package itself
in its resources folder.
"""
import os
import sys
import sysconfig

library = os.path.join(sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("LDLIBRARY"))
if not os.path.isfile(library) or not sysconfig.get_config_var("Py_ENABLE_SHARED"):
    sys.exit(f"this Python has no shared libpython ({library}): pythonfmu cannot be embedded")
print(f"LD_PRELOAD={library}")
print(f"PYTHONHOME={sys.base_prefix}")
