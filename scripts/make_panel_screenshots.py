"""Screenshots of the Design Gallery panel in the real ParaView GUI, for the README.

Runs `paraview` (with the plugin) on the Tooth volume three times, plays an XML event script
each time (Testing/Plugin/Gui/GuiSetup.py sets the scene), waits for ParaView to report the
script finished, grabs the X screen (Pillow) and stops ParaView:
  panel_overview.png  the panel on Tooth: the outline of 50 000 designs with thumbnails;
  panel_query.png     after a query with a shipped ParaView screenshot: the query (red cross),
                      its neighbours (blue), the design's preview and fidelity;
  panel_applied.png   after Apply: the design's TF in the render view and the colour map.

Run under an X server (scripts/with-xvfb.sh sets DISPLAY):
  scripts/with-xvfb.sh /usr/bin/python3 scripts/make_panel_screenshots.py BUILD_DIR [OUT_DIR]
(default OUT_DIR: Documentation/Results).
"""
import os
import subprocess
import sys
import tempfile
import time

from PIL import ImageGrab

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
build = os.path.abspath(sys.argv[1])
out_dir = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "Documentation", "Results")
data = os.path.join(root, "Data")
plugin_dir = None
for base, _, files in os.walk(os.path.join(build, "lib")):
    if "DesignGallery.so" in files:
        plugin_dir = base
if not plugin_dir:
    sys.exit(f"no DesignGallery.so under {build}/lib: build first")

dock = "pqClientMainWindow/pqDDGDesignGalleryDock/scroll/qt_scrollarea_viewport/contents"
query = [
    f'<pqevent object="{dock}/queryBox/queryPath" command="set_string" '
    f'arguments="{data}/Screenshots/tooth_dentin_enamel_oblique.png" />',
    f'<pqevent object="{dock}/queryBox/query" command="activate" arguments="" />',
]
apply = [f'<pqevent object="{dock}/designBox/apply" command="activate" arguments="" />']
shots = {"panel_overview.png": [], "panel_query.png": query, "panel_applied.png": query + apply}

os.makedirs(out_dir, exist_ok=True)
with tempfile.TemporaryDirectory() as tmp:
    env = dict(
        os.environ,
        DDG_GUI_CASE="tooth",
        DDG_DATA_DIR=data,
        DDG_GUI_RECORD=os.path.join(tmp, "record.txt"),
    )
    for name, events in shots.items():
        script = os.path.join(tmp, name + ".xml")
        with open(script, "w") as f:
            f.write(
                '<?xml version="1.0" ?>\n<pqevents>\n  ' + "\n  ".join(events) + "\n</pqevents>\n"
            )
        start = time.time()
        gui = subprocess.Popen(
            [
                "paraview",
                "--dr",
                f"--plugin-search-paths={plugin_dir}",
                "--plugins=DesignGallery",
                f"--script={os.path.join(root, 'Testing', 'Plugin', 'Gui', 'GuiSetup.py')}",
                f"--test-script={script}",
            ],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        finished = False
        try:
            for line in gui.stdout:
                if "FAILED" in line or "Couldn't find object" in line:
                    sys.exit(f"{name}: the GUI events failed: {line.strip()}")
                if "is finished" in line:
                    finished = True
                    break
            if not finished:
                sys.exit(f"{name}: ParaView ended before the events finished")
            time.sleep(3)  # let the views repaint
            image = ImageGrab.grab(xdisplay=os.environ["DISPLAY"])
            box = image.getbbox()  # the windows (the X root is black)
            image = image.crop(box) if box else image
            image.save(os.path.join(out_dir, name))
            print(f"{name}: {image.size[0]}x{image.size[1]} ({time.time() - start:.1f} s)")
        finally:
            gui.kill()
            gui.wait()
