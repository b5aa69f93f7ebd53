"""Helpers shared by the plugin's pvpython tests."""
from paraview import servermanager
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand
from vtkmodules.util.misc import calldata_type


class Errors:
    """Collects the error messages a filter reports (its client-side object: builtin sessions)."""

    def __init__(self, proxy):
        self.messages = []
        self.proxy = proxy

        @calldata_type(VTK_STRING)
        def on_error(obj, event, calldata):
            self.messages.append(calldata)

        proxy.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, on_error)

    def expect(self, label, expected, port=0, **props):
        """Sets `props`, updates: exactly one error containing `expected` and an empty output."""
        self.messages.clear()
        for key, value in props.items():
            setattr(self.proxy, key, value)
        self.proxy.UpdatePipeline()
        data = servermanager.Fetch(self.proxy, idx=port)
        assert data.GetNumberOfElements(0) == 0 and data.GetNumberOfElements(6) == 0, \
            f"{label}: output {port} should be empty"
        assert len(self.messages) == 1, f"{label}: expected one error, got {self.messages}"
        assert expected in self.messages[0], f"{label}: '{expected}' not in '{self.messages[0]}'"
        print(f"{label}: {self.messages[0].strip().splitlines()[-1]}")
