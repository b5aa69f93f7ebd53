# GuiLoadCheck.py: run inside the ParaView GUI (--script): the plugin is loaded (autoload from
# --plugin-search-paths/--plugins), DDG Volume Render exists and runs; writes MARKER on success.
import os
import paraview.simple as simple

marker = os.environ["DDG_GUI_MARKER"]
data = os.environ["DDG_DATA_DIR"]
reader = simple.XMLImageDataReader(FileName=[os.path.join(data, "Volumes", "neghip.vti")])
render = simple.DDGVolumeRender(Input=reader)
render.TransferFunctionFile = os.path.join(data, "TransferFunctions", "neghip_shells.json")
render.ViewFile = os.path.join(data, "Views", "neghip_side.json")
render.UpdatePipeline()
extent = render.GetDataInformation().GetExtent()
if extent[1] == 319 and extent[3] == 319:
    with open(marker, "w") as f:
        f.write("DDGVolumeRender ran in the GUI: %s\n" % (extent,))
