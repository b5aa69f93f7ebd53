"""ddg.plugin: finding and loading the DesignGallery plugin, the connection, and reading filters.

Loading is once per connection, on the client and, when connected to a ``pvserver``, on the
server too (the filters' proxy definitions come from the server). The helpers below update a
filter and read its outputs' field data; the package's other modules build on them.
"""
import importlib
import json
import os
import sys

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


def _server_has_plugin():
    """True when the connected server defines the plugin's filters already (a pvserver started
    with the plugin's folder in ``PV_PLUGIN_PATH``, or loaded before)."""
    definitions = servermanager.ProxyManager().SMProxyManager.GetProxyDefinitionManager()
    return bool(definitions.HasDefinition("filters", "DDGVolumeRender"))


def _client_has_plugin():
    """True when this process has loaded the plugin already (ParaView's GUI started with it:
    loading it again would add a second Design Gallery panel)."""
    info = (
        servermanager.vtkSMProxyManager.GetProxyManager().GetPluginManager().GetLocalInformation()
    )
    return any(
        info.GetPluginName(i) == "DesignGallery" and info.GetPluginLoaded(i)
        for i in range(info.GetNumberOfPlugins())
    )


def _ensure_plugin():
    """Loads the plugin on the client unless it has it and, when connected to a server that does
    not have it yet, on the server: from ``DDG_SERVER_PLUGIN`` (the plugin's path on the server's nodes), else the
    client's path."""
    connection = servermanager.ActiveConnection
    if connection is None:
        simple.Connect()
        connection = servermanager.ActiveConnection
    key = id(connection)
    if key in _loaded:
        return
    path = _plugin_file()
    if connection.IsRemote() and not _server_has_plugin():
        server_path = os.environ.get("DDG_SERVER_PLUGIN") or path
        try:
            simple.LoadPlugin(server_path, remote=True)
        except RuntimeError:  # "Problem loading plugin": said below, with what to do
            pass
        if not _server_has_plugin():
            raise ImportError(
                "ddg: the server could not load the DesignGallery plugin from %s: set "
                "DDG_SERVER_PLUGIN to its path on the server's nodes, or start pvserver with the "
                "plugin's folder in PV_PLUGIN_PATH" % server_path
            )
    if not _client_has_plugin():
        simple.LoadPlugin(path, remote=False)
    _loaded.add(key)


def _vtk_module(name):
    """The plugin's Python-wrapped VTK module ``ddg_vtk.<name>`` (DDGFilters, DDGScene): on the
    path already (build/bin/pvpython), else found beside the plugin (build/python)."""
    try:
        return importlib.import_module("ddg_vtk." + name)
    except ImportError:
        build = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(_plugin_file()))))
        python = os.path.join(os.path.dirname(build), "python")
        if python not in sys.path:
            sys.path.insert(0, python)
        return importlib.import_module("ddg_vtk." + name)


def _history(json_text=""):
    """A vtkDDGDesignHistory (the one writer of history steps: Core's, through the plugin) holding
    the history ``json_text``; raises DDGError for a history it refuses."""
    history = _vtk_module("DDGFilters").vtkDDGDesignHistory()
    if not history.SetJSON(json_text):
        raise DDGError(history.GetError())
    return history


# --- running filters and reading their outputs ------------------------------------------------


def _whole(value, caller, name, low, high=None):
    """A filter's whole-number property, refused outside [low, high] (the filter would clamp it
    silently: iterations=-5 ran one step)."""
    if int(value) != value or value < low or (high is not None and value > high):
        span = ">= %d" % low if high is None else "from %d to %d" % (low, high)
        raise ValueError("%s: %s must be a whole number %s, not %r" % (caller, name, span, value))
    return int(value)


def _within(value, caller, name, low, high):
    """A filter's number property, refused outside [low, high] (not clamped silently)."""
    if not low <= float(value) <= high:
        raise ValueError("%s: %s must lie in [%g, %g], not %r" % (caller, name, low, high, value))
    return float(value)


def _run(proxy):
    """Updates a filter; raises DDGError with its message when it failed."""
    proxy.UpdatePipeline()
    proxy.UpdatePropertyInformation()
    error = proxy.GetPropertyValue("LastError") if proxy.GetProperty("LastError") else ""
    if error:
        raise DDGError(error)


def _kind_network(kind, caller):
    """The filters' KindNetwork for ``kind=``: True the shipped Data/Models/kind (when it is
    there), a directory that kind network, False none."""
    if kind is True:
        shipped = data_path("Models/kind")
        return shipped if os.path.exists(os.path.join(shipped, "kind.json")) else ""
    if not kind:
        return ""
    if not os.path.exists(os.path.join(str(kind), "kind.json")):
        raise DDGError("%s: %r is not a kind network (no kind.json)" % (caller, kind))
    return os.path.abspath(str(kind))


def _kind_of(table):
    """A result's kind check (the "Kind" field) as a dict, or None."""
    text = _field_string(table, "Kind")
    return json.loads(text) if text else None


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
