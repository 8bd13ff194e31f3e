# SPDX-License-Identifier: MIT
# Run by pvbatch (tests/test_paraview.sh): open particles.xdmf as a ParaView user does (File >
# Open picks the default reader for the file; the animation scene takes the file's time steps;
# the data are shown in a render view), step through every time, and print one JSON line per
# time step with the reader's name, the number of cells and points, and the range of every cell
# array. With a second argument, also save a screenshot of the last time step coloured by vy.
import json
import sys

from paraview.simple import (OpenDataFile, GetAnimationScene, GetActiveViewOrCreate, Show,
                             ColorBy, Render, SaveScreenshot)

reader = OpenDataFile(sys.argv[1])
if reader is None:
    print(json.dumps({'error': 'ParaView found no reader for ' + sys.argv[1]}))
    sys.exit(1)
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
view = GetActiveViewOrCreate('RenderView')
display = Show(reader, view)
times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
for t in times:
    scene.AnimationTime = t
    Render(view)
    info = reader.GetDataInformation()
    arrays = {}
    for name in reader.CellData.keys():
        a = reader.CellData[name]
        lo, hi = a.GetRange(0)
        arrays[name] = [a.GetNumberOfComponents(), lo, hi]
    print(json.dumps({'reader': reader.GetXMLName(), 'time': t, 'cells': info.GetNumberOfCells(),
                      'points': info.GetNumberOfPoints(), 'arrays': arrays}))
if len(sys.argv) > 2:
    ColorBy(display, ('CELLS', 'vy'))
    view.ResetCamera()
    Render(view)
    SaveScreenshot(sys.argv[2], view, ImageResolution=[640, 480])
