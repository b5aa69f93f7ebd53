"""ddg.plugin: finding and loading the DesignGallery plugin, the connection, and reading filters.

Loading is once per connection, on the client and, when connected to a ``pvserver``, on the
server too (the filters' proxy definitions come from the server). The helpers below update a
filter and read its outputs' field data; the package's other modules build on them.
"""
import os

import numpy as np
from paraview import servermanager
import paraview.simple as simple

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.dirname(os.path.dirname(_HERE))


class DDGError(RuntimeError):
    """A filter reported an error (the message is the filter's)."""


def data_path(relative=""):
    """A path in the project's Data/ directory (``DDG_DATA_DIR`` or next to the package)."""
    return os.path.join(os.environ.get("DDG_DATA_DIR", os.path.join(_ROOT, "Data")), relative)


def _plugin_file():
    path = os.environ.get("DDG_PLUGIN")
    if not path:
        path = os.path.join(
            _ROOT, "build", "lib", "paraview-5.11", "plugins", "DesignGallery", "DesignGallery.so"
        )
    if not os.path.exists(path):
        raise ImportError(
            "ddg: the DesignGallery plugin was not found at %s; build it "
            "(bash scripts/build.sh) and use build/bin/pvpython, or set DDG_PLUGIN" % path
        )
    return path


_loaded = set()


def _ensure_plugin():
    """Loads the plugin on the client and, when connected to a server, on the server."""
    connection = servermanager.ActiveConnection
    if connection is None:
        simple.Connect()
        connection = servermanager.ActiveConnection
    key = id(connection)
    if key in _loaded:
        return
    path = _plugin_file()
    if connection.IsRemote():
        simple.LoadPlugin(path, remote=True)
    simple.LoadPlugin(path, remote=False)
    _loaded.add(key)


# --- running filters and reading their outputs ------------------------------------------------


def _run(proxy):
    """Updates a filter; raises DDGError with its message when it failed."""
    proxy.UpdatePipeline()
    proxy.UpdatePropertyInformation()
    error = proxy.GetPropertyValue("LastError") if proxy.GetProperty("LastError") else ""
    if error:
        raise DDGError(error)


def _field_string(table, name):
    a = table.GetFieldData().GetAbstractArray(name)
    return a.GetValue(0) if a is not None else None


def _field_numbers(table, name):
    a = table.GetFieldData().GetArray(name)
    return (
        np.array([a.GetValue(i) for i in range(a.GetNumberOfValues())]) if a is not None else None
    )


def _tf_text(table):
    """The TF a filter wrote into its table's field data: ``Preset`` (1D, a ParaView preset list)
    or ``TransferFunction2D`` (the DDG 2D JSON); None when there is neither."""
    return _field_string(table, "Preset") or _field_string(table, "TransferFunction2D")


def _first_tf(tf):
    """The TF of a preset list (its first entry) or the TF dict itself."""
    return tf[0] if isinstance(tf, list) else tf
