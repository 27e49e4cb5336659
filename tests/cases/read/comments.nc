(comments: parentheses do not nest; a semicolon hides the rest of the line)
G21 G18
G0 X100 Z50 (a comment (with a parenthesis) leaves this outside)
G0 X100 Z50 ; G1 X-1000 is hidden, so no overtravel
G0 X100 (unclosed comment
(MSG, a message comment)
G0 X100 Z50
M30
