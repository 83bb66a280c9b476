IG
# two unit quads sharing an edge, and a one-edge branch at vertex 0 (reference-notes 2.1)
7 8 2
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
-1 -1 0
0 1
1 2
3 4
4 5
0 3
1 4
2 5
0 6
4 0 5 2 4
4 6 1 5 3
