// Line 3 misses a comma: gmsh reports "line 3: syntax error".
Point(1) = {0, 0, 0, 0.1};
Point(2) = {1, 0, 0 0.1};
