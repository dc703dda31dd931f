"""Opens a parallel run's points.pvtu with VTK's own reader and compares it with
a single-process run's points.vtu, array by array (README, "Beyond one machine").

    pip install vtk numpy
    python3 tests/mpi/read_pvtu.py ONE_PROCESS_OUT SEVERAL_PROCESSES_OUT

Exits non-zero when the reader fails, a point is missing or a value differs by
more than 1e-8 of the array's largest magnitude (the solves agree to that).
"""
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def read(path, reader):
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main(one, several):
    whole = read(f"{one}/points.vtu", vtk.vtkXMLUnstructuredGridReader())
    parallel_reader = vtk.vtkXMLPUnstructuredGridReader()
    parallel = read(f"{several}/points.pvtu", parallel_reader)
    pieces = parallel_reader.GetNumberOfPieces()
    n = whole.GetNumberOfPoints()
    print(f"points.vtu: {n} points; points.pvtu: {parallel.GetNumberOfPoints()} points "
          f"in {pieces} pieces")
    if parallel.GetNumberOfPoints() != n or parallel.GetNumberOfCells() != n:
        sys.exit("the pieces do not hold every point once")
    arrays = [("points", vtk_to_numpy(whole.GetPoints().GetData()),
               vtk_to_numpy(parallel.GetPoints().GetData()))]
    data = whole.GetPointData()
    for k in range(data.GetNumberOfArrays()):
        name = data.GetArrayName(k)
        other = parallel.GetPointData().GetArray(name)
        if other is None:
            sys.exit(f"points.pvtu lacks the array {name}")
        arrays.append((name, vtk_to_numpy(data.GetArray(k)), vtk_to_numpy(other)))
    worst = 0.0
    for name, a, b in arrays:
        scale = max(np.abs(a).max(), 1e-300)
        difference = np.abs(a - b).max() / scale
        worst = max(worst, difference)
        print(f"  {name:13s} {a.shape} largest difference {difference:.1e} of max|value|")
    if worst > 1e-8:
        sys.exit("the parallel file differs from the single-process one")


if __name__ == "__main__":
    main(*sys.argv[1:3])
